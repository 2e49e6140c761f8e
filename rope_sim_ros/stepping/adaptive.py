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

"""
The adaptive integrator: implicit steps while tensions change slowly, improved Euler in a snap.

Implicit Euler at its few-millisecond step carries a line in ship motion at a hundred times
real time, but it damps the axial waves that carry a snap load (a slack line jerked taut
peaked 31 % low at its automatic step) and, at a damping of about w h / 2 of critical, the
slow motions too (a 5 t payload's 3 Hz bounce on its wire, so that the snatches after the
first came at other times and 89-98 % low). Improved Euler at its stable step (a fraction of
a millisecond) gets every one of those peaks within 0.5 %, at a sixth of the speed.

So the adaptive integrator takes the implicit step in Newmark's form with gamma = GAMMA and
beta = (gamma + 1/2)^2 / 4, second order in all but the gamma - 1/2 that damps a motion by
about (gamma - 1/2) w h / 2 of critical (a tenth of implicit Euler's at gamma 0.55; gamma =
1/2, which damps nothing, blew up where a slack segment came taut), and it watches every
segment after every step (parting.check_segments). A step in which

- a segment's spring tension changed by more than SNAP_TOLERANCE of the line's scale per
  step (over two steps: a stiff end segment rings up and down every step, which is no snap),
- or a slack segment moved so that, came taut, it would pull more than that (sqrt(EA m) times
  its stretch rate: the impact of a slack line caught, before it is caught),

is taken again from its start with improved Euler at its stable step, and improved Euler
goes on until the line has been calm for HOLD_TIME: no improved Euler step in that time
changed a spring tension by more than CALM_TOLERANCE of the scale per implicit step (nor
moved a slack segment as above). Then implicit steps try again. Taken again, not corrected:
the implicit step's damped wave never reaches an output, and the peak is the explicit one.

The scale is the line's largest segment tension in the step, and never less than
model/parting.py's SNAP_FLOOR_WEIGHT times its weight nor SNAP_FLOOR_MBL of its MBL: on a
slack line every change is a large part of a small tension (a stiff HMPE spring fallen slack
to 0.9 kN as its ship surged went to improved Euler at most steps). The MBL's share keeps
such changes, which break nothing, out; at 1 % of the MBL the jerked line of test_snap_loads
was seen late (3.8 % low), at 0.5 % not (0.2 %).

Why a change per step: an implicit step damps a motion that changes the tension by a
fraction r of the scale per step by the order of r times its amplitude, so a change below
SNAP_TOLERANCE bounds what it takes off a peak to a few per cent of the scale.

Why until calm, not for a fixed time: a snap leaves the line vibrating, and the vibration
carries load. A line driven slack and taut again and again (test_slack_taut.py: 50 m of
48 mm HMPE in air, its fairlead surging 1 m at 8 s about 0.8 m short of taut) whips across
as its sag is pulled out, and in air, with only its axial dampers on it, goes on vibrating
across through the whole taut phase (+-0.3 m at mid-span in one such case), which stretches
it (a transverse vibration of energy E adds about EA E / (L T) to a taut line's tension T)
and drives an axial ringing (+-10 kN on 320 kN). Implicit steps damp it: Newmark's
(gamma - 1/2) w h / 2 of critical grows with the mode, and in that case the vibration's
kinetic energy fell tenfold within the taut phase where improved Euler's kept it. Held for a
fixed 0.1 s after each snap, the test's line spent 21 % of its time in improved Euler and
its mean tension came 2.9 % and its cycle peaks 2.8-5.4 % below improved_euler's at 2e-5 s;
held until calm, 45 % of its time, within 0.3 % and 1.3 %. On 28 such cases (20-50
segments, surges of 0.15-1 m at 3-15 s, in air and in water) the mean came within 1.4 %
(before: up to 2.9 % low) and every cycle's peak within 3.7 % (before: up to 11 % low), at
1.0-2.6 times the CPU of the fixed hold, about improved_euler's or less. In water the drag
damps the vibration: there the fixed hold was already right, and nothing changed. A line
that does not snap is never held, and pays nothing.

CALM_TOLERANCE: the ringing a hold leaves changes the tension by about this much per step,
and it is what implicit steps then take off a peak. At 2 % the cases' cycle peaks came up
to 4.7 % low, at 1 % 3.7 %. A tension rising with the ship changes by far less (a few
tenths of a per cent per step on those springs), so holds end once the ringing has died.

The calm watch's scale is at least model/parting.py's CALM_FLOOR_FACTOR (10) times the snap
watch's floor: a line fallen slack rings about almost nothing. On the snap watch's floor
alone (0.5 % of the MBL) a slack 44 mm HMPE spring of a berth in ship motion, at 1 kN,
rang by 0.36 kN a step and was never calm: it stayed in improved Euler the whole run, and
the sixteen-line berth with it took 75 % of a core; with the floor, 37-44 %. The slack-taut
case above: mean -0.1 %, cycle peaks -1.3 %, -0.4 %, -0.9 % (improved Euler 35 % of the
time); at 40 times the floor, -0.8 % and up to -2.3 %, for no further speed.

Measured and left: less numerical damping instead (gamma 0.50-0.51) still left cycle peaks
from 7 % low to 4.6 % high, the first implicit step after a hold being implicit Euler's
(Newmark's needs the accelerations of the step before); starting that step from the state's
own accelerations, gamma 0.5 and 0.502 gained energy (peaks up to 21 % high). A fixed hold
of 2 s still left a cycle peak 4.1 % low, and costs every snap 2 s of improved Euler. A
SNAP_TOLERANCE of 0.02 still left cycle peaks 4-6 % low, and improved Euler wherever a slack
segment moved changed nothing: the snap itself was caught; what went missing came after it.

The improved Euler steps take the driven ends along the cubic Hermite curve through the
implicit steps' samples (positions and velocities), which is the end's own cubic within one
sample interval of its trajectory.
"""

import numba
import numpy as np

from .kernels import run_kernel
from ..model.layout import (CALM_CHANGE, HISTORY, PARTED, PARTED_STEP, SLACK_IMPACT,
                            TENSION_CHANGE)

SNAP_TOLERANCE = 0.05
CALM_TOLERANCE = 0.01
HOLD_TIME = 0.1  # [s]
GAMMA = 0.55
NEWMARK = (GAMMA, 0.25 * (GAMMA + 0.5) ** 2)


def run(system, dt, drive_x, drive_v, fine_steps, max_iterations, implicit_bending, compiled):
    """
    Take len(drive_x) adaptive steps of dt of `system` in place (see the module's docstring).

    Every step is judged on its own, so that the outcome does not depend on how the steps
    are split into runs (a live stream and a whole motion file give the same numbers). Lines
    whose ends are all fixed or driven are judged each on its own, and a line's improved
    Euler steps are its own step's: in a System of many lines, each steps as it would alone.
    So does a line whose free end is its own (a payload, a line let go). Lines joined by free
    points are judged together, at the smallest of their steps. While no line is in improved
    Euler, the run is first tried in one kernel call; only where a step in it snapped is the
    run taken again step by step.

    :param system: an objects.System; its fine_left (each line's improved Euler time left
        [s]) and its lines' HISTORY are this integrator's state.
    :param fine_steps: the largest stable improved Euler step now [s], of every line or of
        each line (L,).
    Other arguments as System.step. A line that parts gets its PARTED_STEP in steps of dt
    from the start of the run (a fraction where it parted in an improved Euler step).
    """
    real = system.line_real
    if not system.history_kept:
        real[:, HISTORY] = 0.0
    whole = np.empty(len(real), dtype=np.bool_)
    snapped = np.empty(len(real), dtype=np.bool_)
    if not system.fine_left.max(initial=0.0) > 1e-9:  # (rounding of the hold)
        saved = system.save_state()
        if not _take(system, 'implicit_euler', dt, drive_x, drive_v, 0, 1, max_iterations,
                     implicit_bending, compiled, NEWMARK, whole, snapped):
            real[:, HISTORY] = 1.0
            return
        system.load_state(saved)
    fine_steps = np.broadcast_to(np.asarray(fine_steps, dtype=float), (len(real),))
    if not (fine_steps > 0.0).all():
        raise ValueError(f'the adaptive step needs improved Euler steps > 0, not {fine_steps}')
    # (judged together, one line let go of sixteen took all sixteen through its snap in
    # improved Euler: 2.3 ms an output for 0.6, and 15 let go 1.8 s behind the clock)
    together = system.joins_lines
    for k in range(len(drive_x)):
        _step(system, dt, drive_x[k:k + 1], drive_v[k:k + 1], k, fine_steps, together,
              max_iterations, implicit_bending, compiled, whole, snapped)


def _step(system, dt, step_x, step_v, k, fine_steps, together, max_iterations,
          implicit_bending, compiled, whole, snapped):
    """Take step k of a run: implicit where no line snaps, else again with improved Euler."""
    real = system.line_real
    fine = system.fine_left > 1e-9
    saved = system.save_state()
    implicit = None
    if not fine.all() or system.has_bodies:  # a body moves in the implicit step only
        _take(system, 'implicit_euler', dt, step_x, step_v, k, 1, max_iterations,
              implicit_bending, compiled, NEWMARK, whole, snapped)
        if not (fine | snapped).any():
            real[:, HISTORY] = 1.0
            return
        implicit = system.save_state()  # a snap: the step again, with improved Euler
        system.fine_left[snapped] = HOLD_TIME
        fine |= snapped
    if system.has_bodies:  # the fine lines' carried ends follow the body's implicit step
        step_x, step_v = _carried_ends(system, step_x, step_v)
    if together:
        fine[:] = True
    _take_fine(system, dt, step_x, step_v, k, fine, fine_steps, together, saved, implicit,
               max_iterations, implicit_bending, compiled, whole, snapped)
    real[:, HISTORY] = ~fine
    system.fine_left[fine] -= dt
    system.fine_left[fine & snapped] = HOLD_TIME  # not calm yet: the hold starts again


def _carried_ends(system, step_x, step_v):
    """
    Return the step's drive arrays with each carried point where the implicit step left it.

    A line taken again with improved Euler (on a LineView, its carried end a driven one)
    then moves its end along the body's own path through the step: the body's motion is the
    implicit step's, its lines' snap the improved Euler steps'. (A ship's motion in one step
    is far too slow for the difference to reach its lines.)
    """
    carried = system.carried_points
    if not len(carried):
        return step_x, step_v
    step_x, step_v = step_x.copy(), step_v.copy()
    step_x[:, carried] = system.point_x[carried]
    step_v[:, carried] = system.point_v[carried]
    return step_x, step_v


def _take_fine(system, dt, step_x, step_v, k, fine, fine_steps, together, saved, implicit,
               max_iterations, implicit_bending, compiled, whole, snapped):
    """
    Take step k again with improved Euler for the `fine` lines, each at its own step.

    From `saved` (the state before the step). Lines joined by free points: one run of the
    whole System at their smallest step. Other lines: each fine line alone, on a view of its
    rows (objects.LineView), the other lines keeping their implicit step: a berth's stiff
    spring coming taut costs that line's improved Euler steps, not its whole group's.
    """
    if together:
        system.load_state(saved)
        _take_parts(system, dt, step_x, step_v, k, float(fine_steps[fine].min()),
                    max_iterations, implicit_bending, compiled, whole, snapped)
        return
    for line in np.flatnonzero(fine):
        if implicit is not None:  # the others' implicit step stands; this line's goes
            system.load_line_state(saved, line)
        view = system.line_view(line)
        view.point_x[:], view.point_v[:] = saved[2][view.ends], saved[3][view.ends]
        _take_parts(view, dt, *view.drive(step_x, step_v), k, float(fine_steps[line]),
                    max_iterations, implicit_bending, compiled, whole[line:line + 1],
                    snapped[line:line + 1])
        view.store_points(system)


def _take_parts(system, dt, step_x, step_v, k, fine_step, max_iterations, implicit_bending,
                compiled, whole, snapped):
    """Take step k in improved Euler steps no longer than fine_step, the ends on the cubic."""
    parts = max(1, int(np.ceil(dt / fine_step - 1e-9)))
    fine_x, fine_v = hermite(system.point_x, system.point_v, step_x, step_v, dt, parts)
    _take(system, 'improved_euler', dt / parts, fine_x, fine_v, k, parts, max_iterations,
          implicit_bending, compiled, (1.0, 0.5), whole, snapped)


def _take(system, integrator, dt, drive_x, drive_v, first, parts, max_iterations,
          implicit_bending, compiled, newmark, whole, snapped):
    """
    Take one kernel run from a cleared watch; set `snapped` to the lines that snapped in it.

    A run of improved Euler steps is judged against CALM_TOLERANCE: `snapped` are then the
    lines not calm yet. A parting's step is put in the run's steps of parts * dt from
    `first`. A line the system does not watch (its `watched`) never snaps. Returns whether
    any line snapped.
    """
    _clear_watch(system.line_real, whole)
    run_kernel(system, integrator, dt, drive_x, drive_v, max_iterations, implicit_bending,
               compiled, newmark)
    anything = _read_watch(system.line_real, whole, first, parts, snapped,
                           integrator != 'implicit_euler')
    if anything and not system.watched.all():
        snapped &= system.watched
        anything = bool(snapped.any())
    return anything


@numba.njit(cache=True)
def _clear_watch(line_real, whole):
    """Clear every line's watch columns; note which lines are whole (in `whole`)."""
    for k in range(line_real.shape[0]):
        line_real[k, TENSION_CHANGE] = 0.0
        line_real[k, CALM_CHANGE] = 0.0
        line_real[k, SLACK_IMPACT] = 0.0
        whole[k] = line_real[k, PARTED] < 0.0


@numba.njit(cache=True)
def _read_watch(line_real, whole, first, parts, snapped, calm):
    """
    Set `snapped` to the lines whose tensions changed faster than implicit steps follow.

    In a step of the run, a spring tension changing by more than SNAP_TOLERANCE of the line's
    scale (with `calm`, a run of improved Euler steps: CALM_TOLERANCE of its calm scale; parts
    improved Euler steps count as one implicit step), or a slack segment that would come taut
    with more than SNAP_TOLERANCE. Also times the partings of the run. Returns whether any
    line snapped.
    """
    anything = False
    for k in range(line_real.shape[0]):
        if whole[k] and line_real[k, PARTED] >= 0.0:
            line_real[k, PARTED_STEP] = first + (line_real[k, PARTED_STEP] + 1.0) / parts - 1.0
        change = (line_real[k, CALM_CHANGE] * parts > CALM_TOLERANCE if calm
                  else line_real[k, TENSION_CHANGE] * parts > SNAP_TOLERANCE)
        snapped[k] = change or line_real[k, SLACK_IMPACT] > SNAP_TOLERANCE
        anything |= snapped[k]
    return anything


def hermite(point_x, point_v, drive_x, drive_v, dt, parts):
    """
    Return driven points at `parts` equal substeps of each step, (n parts, Q, 3) twice.

    Each step goes from the points' state before it (point_x, point_v for the first, then the
    previous sample) to its sample (drive_x, drive_v: (n, Q, 3)) along the cubic Hermite
    curve through both ends' positions and velocities.
    """
    x0 = np.concatenate([point_x[None], drive_x[:-1]])
    v0 = np.concatenate([point_v[None], drive_v[:-1]])
    s = (np.arange(1, parts + 1) / parts)[None, :, None, None]
    s2, s3 = s * s, s * s * s
    x0, v0 = x0[:, None], v0[:, None]
    x1, v1 = drive_x[:, None], drive_v[:, None]
    x = ((2 * s3 - 3 * s2 + 1) * x0 + (s3 - 2 * s2 + s) * dt * v0
         + (3 * s2 - 2 * s3) * x1 + (s3 - s2) * dt * v1)
    v = ((6 * s2 - 6 * s) * (x0 - x1) / dt + (3 * s2 - 4 * s + 1) * v0
         + (3 * s2 - 2 * s) * v1)
    shape = (len(drive_x) * parts,) + drive_x.shape[1:]
    return x.reshape(shape), v.reshape(shape)
