# Copyright 2026 rope_sim_ros contributors
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

"""The unstretched length of a line that pulls its fairlead with a given tension at rest."""

import math

import numpy as np

from .catenary import CatenaryError, solve_catenary
from ..objects import Environment
from ..rope import RopeProperties


class PretensionError(ValueError):
    """No length gives the line that tension between its ends; the message says why."""


# Bisection steps of length_for_tension (2^-60 of the bracket: far below a micrometre).
LENGTH_BISECTIONS = 60


def length_for_tension(props: RopeProperties, environment: Environment, bollard, fairlead,
                       tension: float) -> float:
    """
    Return the unstretched length whose elastic catenary pulls the fairlead with `tension`.

    The catenary in air (the line's weight less the air's buoyancy, weight_per_length)
    between the bollard and the fairlead, stretched by the line's strain-tension curve where
    it has one (else EA); a weightless line is a straight elastic bar. The
    fairlead tension falls as the line grows, down to the least it can have hanging between
    its ends; bisection between the line at its reach and that.

    :raises PretensionError: the tension is more than the line pulls at its reach (its
        limit_tension) or less than the least it can have between these ends.
    """
    up = -np.asarray(environment.gravity, dtype=float)
    g = float(np.linalg.norm(up))
    up = up / g if g > 0.0 else np.array([0.0, 0.0, 1.0])
    chord = np.asarray(fairlead, dtype=float) - np.asarray(bollard, dtype=float)
    distance = float(np.linalg.norm(chord))
    rise = float(chord @ up)
    span = math.sqrt(max(distance * distance - rise * rise, 0.0))
    ea, w = props.axial_stiffness, props.weight_per_length(environment)
    strongest = props.limit_tension
    if not distance > 0.0:
        raise PretensionError('pretension needs the fairlead away from the bollard: they are '
                              'at one place at the first ship pose')
    if tension >= strongest:
        raise PretensionError(f'pretension {tension:.0f} N is not below what the line pulls at '
                              f'its reach ({strongest:.0f} N at its strain limit)')
    if not w > 0.0:
        return distance / (1.0 + float(props.strain_at(tension)))

    def fairlead_tension(length: float) -> float:
        return solve_catenary(span, rise, length, w, ea, props.curve).tension_b

    low, high = distance / (1.0 + props.strain_limit), distance
    try:
        least = fairlead_tension(high)
        while least > tension:  # longer lines until one pulls less, or the tension grows
            longer = fairlead_tension(high * 1.25)
            if longer >= least:
                raise PretensionError(
                    f'pretension {tension:.0f} N is below the least fairlead tension the '
                    f'line can have between its ends ({least:.0f} N, hanging under its '
                    'weight)')
            low, high, least = high, high * 1.25, longer
        for _ in range(LENGTH_BISECTIONS):
            middle = 0.5 * (low + high)
            if fairlead_tension(middle) > tension:
                low = middle
            else:
                high = middle
    except CatenaryError as e:
        raise PretensionError(f'pretension {tension:.0f} N: no catenary between the ends: '
                              f'{e}') from None
    return 0.5 * (low + high)
