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
The record that carries a System's arrays into the compiled kernels, as one: SystemArrays.

A SystemArrays holds the arrays the integrators read and write (stepping/kernels.py): the
state (x, v, point_x, point_v, accel, point_accel) and the tables of layout.py (particles,
lines, line_real, points, env, bodies, fenders). It holds the System's own arrays, not
copies: a kernel that writes arrays.x writes System.x. Named for what it holds, a System's
arrays: a mooring's Group (mooring/group.py) is a set of lines stepped together, with a
System of its own.

It is a numba StructRef: one reference, unboxed in one step, where the kernels took 20
positional arrays. benchmarks/record_overhead.py, a kernel of no work on a 50-segment
System, four runs: a call took 0.85-0.97 times as long with the StructRef as with the
positional arrays (0.83-0.93 us against 0.96-0.98 us on a quiet machine); 1.1-1.3 times with
a plain tuple and 2.2-2.6 times with a NamedTuple (numba types each of their arrays in Python
at every call); 0.6-0.7 times with a jitclass, but numba cannot cache a kernel that takes
one (every start would compile them all again). Making a SystemArrays costs about 3.6 us: a
System makes one when it packs or refreshes its tables, a LineView one each time it is made.

A kernel reads a record's fields once, before its step loop, and hands its steps the arrays:
numba takes and drops a reference count at each read of a field that it cannot prove
needless, which inside a step loop cost a small line's implicit step up to 19 %
(kernels.implicit_euler_run).

In Python (a kernel's interpreted code, ``.py_func``, which the tests run) a SystemArrays'
fields are the very arrays it was made of. An array joins the record as one more name in
FIELDS (and one more argument where a System and a LineView make their SystemArrays).
"""

import numba
from numba.core import types
from numba.experimental import structref

# the fields, in the order SystemArrays takes them
FIELDS = ('x', 'v', 'point_x', 'point_v', 'accel', 'point_accel', 'particles', 'lines',
          'line_real', 'points', 'env', 'bodies', 'fenders')


@structref.register
class SystemArraysType(types.StructRef):
    """numba's type of a SystemArrays: the types of its arrays."""


class SystemArrays(structref.StructRefProxy):
    """
    A System's arrays as one record for the kernels (see the module's docstring).

    :ivar x, v: particle positions and velocities (P, 3), every line's rows stacked.
    :ivar point_x, point_v: point positions and velocities (Q, 3).
    :ivar accel, point_accel: the accelerations of the last implicit step (P, 3), (Q, 3).
    :ivar particles, lines, line_real, points, env, bodies, fenders: the tables of layout.py.
    """

    def __new__(cls, *arrays):
        """Make the record of these arrays, in the order of FIELDS (shared, not copied)."""
        if len(arrays) != len(FIELDS):
            raise TypeError(f'a SystemArrays takes {len(FIELDS)} arrays '
                            f'({", ".join(FIELDS)}), not {len(arrays)}')
        record = _new_record(*arrays)
        # in Python (py_func) its fields are the arrays themselves: a StructRef has none
        vars(record).update(zip(FIELDS, arrays))
        return record


structref.define_proxy(SystemArrays, SystemArraysType, list(FIELDS))


@numba.njit(cache=True)
def _new_record(*arrays):
    """Make a SystemArrays in compiled code (cached, where numba's own constructor is not)."""
    return SystemArrays(*arrays)
