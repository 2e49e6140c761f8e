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
Column layout of the flat tables the numba kernels take (built by objects.System).

numba passes a few 2-D tables far faster than dozens of arrays (each argument costs its
dispatch), so a System packs its lines and points into the tables below, and hands them with
its state to the kernels as one record (record.py); these names say which column holds what.

PARTICLE table (P, PARTICLE_COLUMNS), one row per particle of every line, lines stacked:
    MASS: lumped mass [kg], half of each neighbouring segment (an end: half of one);
    INV_MASS: the strain-limit projection's inverse mass, relative to the line's heaviest
        particle m_u: m_u / MASS inside a line, 0 at an end on a fixed or driven point,
        m_u / (the point's lumped mass) at an end on a free one;
    DRAG: air drag factor K_A times the lumped length [N s^2 / m^2];
    REST, STIFFNESS, DAMPING: the structural spring (i, i + 1) starting at this particle:
        rest length l_i [m], EA / l_i [N/m], BA / l_i [N s/m] (unused on a line's last row);
    BEND_REST, BEND_STIFFNESS, BEND_DAMPING: the bending spring (i, i + 2): rest length
        l_i + l_{i+1}, r_s EA / l_b, r_d BA / l_b with l_b = (l_i + l_{i+1}) / 2;
    LENGTH: the line's length lumped at the particle (half of each neighbouring segment) [m];
    SINK: the contact damping's ramp depth [m];
    REST_RATE: how fast the winch changes l_i [m/s]: the damper acts on the stretch rate,
        the rate of the length less the rate of the rest length;
    TENSION, TENSION_BEFORE: state: the structural spring's elastic tension after the last
        step and after the one before [N] (NaN until a step has measured it), from which the
        adaptive integrator's watch measures its change (parting.check_segments).

LINE table (L, LINE_COLUMNS), integers: FIRST, LAST (its particle rows), END_A, END_B (the
points its particles FIRST and LAST sit on), AXIAL (1: axial damping, 0: the seed's
K_SD (V_A - V_B)), BENDING (1 if it has bending springs), ADJUST (1: apply the strain limit),
FLUID (1 if water or air acts on it beyond the seed's drag: a diameter or a volume diameter,
and water or air of a density above 0 around it),
TANGENTS (1 if its fluid terms need the particles' tangents: drag or unequal added masses).

LINE_REAL table (L, LINE_REAL_COLUMNS): MAX_STRAIN, AXIAL_STIFFNESS (EA [N]), DIAMETER (d, for
drag and contact [m]), VOLUME_DIAMETER (dv, the surface ramp's width [m]), VOLUME_AREA
(A_v = pi dv^2 / 4 [m^2]), NORMAL_DRAG (1/2 Cd d [m]), TANGENTIAL_DRAG (1/2 CdAx pi d [m]),
NORMAL_ADDED_MASS (Ca), TANGENTIAL_ADDED_MASS (CaAx); then the winch's, parting's and peak
hold's columns, listed below, some of which the step writes (winch.py, parting.py); then the
line's strain-tension curve (tension_curve.py): CURVE_POINTS, its number of points n (0: a
linear line, EA), and from CURVE_STRAIN, CURVE_TENSION and CURVE_SLOPE CURVE_CAPACITY columns
each: the points' strains and tensions [N] (the first (0, 0)) and the slope of the segment
that starts at each point [N per unit strain] (the last one's continues past the table). A
fixed number of columns keeps every kernel's arguments as they are; 32 points (MoorDyn reads
at most 30 from its table files, plus the (0, 0) it leaves implied) cost a line 0.8 kB. The
curve comes last so that its size can change without moving any other column.

POINT table (Q, POINT_COLUMNS): KIND (FIXED, DRIVEN, FREE or CARRIED), OWN_MASS [kg], TOTAL_MASS
(own mass plus the half segments of every line end on it [kg]); a free point's VOLUME [m^3],
DRAG_AREA (CdA [m^2]), ADDED_MASS (coefficient Ca_p), SIZE (V^(1/3): its surface ramp's width
and contact width and length [m]) and POINT_SINK (its contact's damping ramp depth [m]); a
carried point's POINT_BODY (its body's row) and POINT_OFFSET (3: where it sits on the body, from
the body's centre of gravity, in body axes [m]).

BODY table (B, BODY_COLUMNS): a rigid body in six degrees of freedom (a free ship), its state
first (the step writes it), then what it is (forces/body.py says how each term acts). Its
reference point is its centre of gravity; velocities, loads and moments are in world axes,
the mass, damping and restoring it is given in body axes. Last, what a hydrodynamic database
gives it: the full added mass at infinite frequency and the modes of its radiation memory,
whose states (MODE_STATE) the step writes too (the Cummins equation, model/ship/radiation.py).

FENDER table (F, FENDER_COLUMNS): a fender on the quay that a body's hull side pushes on: its
face's place and its outward normal (out of the quay, toward the ship), the friction
coefficient against the hull, the body it touches, and its load-compression curve as
FENDER_POINTS (compression [m], reaction [N]) pairs from (0, 0) (forces/fender.py).
"""

MASS = 0
INV_MASS = 1
DRAG = 2
REST = 3
STIFFNESS = 4
DAMPING = 5
BEND_REST = 6
BEND_STIFFNESS = 7
BEND_DAMPING = 8
LENGTH = 9
SINK = 10
REST_RATE = 11
TENSION = 12
TENSION_BEFORE = 13
PARTICLE_COLUMNS = 14

FIRST = 0
LAST = 1
END_A = 2
END_B = 3
AXIAL = 4
BENDING = 5
ADJUST = 6
FLUID = 7
TANGENTS = 8
LINE_COLUMNS = 9

MAX_STRAIN = 0
AXIAL_STIFFNESS = 1
DIAMETER = 2
VOLUME_DIAMETER = 3
VOLUME_AREA = 4
NORMAL_DRAG = 5
TANGENTIAL_DRAG = 6
NORMAL_ADDED_MASS = 7
TANGENTIAL_ADDED_MASS = 8
# the winch, parting and peak hold (winch.py, parting.py); the step writes the state columns
UNSTRETCHED = 9  # state: the line's unstretched length [m] (the winch changes it)
WINCH_MODE = 10  # NO_WINCH, SPEED, BRAKE or CONSTANT_TENSION
WINCH_END = 11  # the end the winch sits on: 0 (A) or 1 (B)
WINCH_COMMAND = 12  # SPEED: commanded pay-out speed [m/s]; CONSTANT_TENSION: set tension [N]
WINCH_MAX_SPEED = 13  # [m/s]
WINCH_ACCELERATION = 14  # [m/s^2]
WINCH_BRAKE_LOAD = 15  # BRAKE: the load above which the brake renders [N]
WINCH_RESPONSE = 16  # CONSTANT_TENSION: how fast it brings the tension to the set one [s]
WINCH_MIN_LENGTH = 17  # the winch stops at these unstretched lengths [m]
WINCH_MAX_LENGTH = 18
WINCH_SPEED = 19  # state: the pay-out speed of the last step [m/s] (+ pays out)
BREAK_LOAD = 20  # a segment whose tension exceeds it parts [N]; inf: never
PARTED = 21  # state: the parted segment's index in the line, -1 while whole
PARTED_STEP = 22  # state: the step of the run in which it parted (0-based), -1 if none
PEAK_A = 23  # state: the largest end force on end A's point since it was cleared [N]
PEAK_B = 24  # likewise end B
WINCH_RAMP = 25  # state: the winch's acceleration in the last step [m/s^2]
# state, since they were cleared, as fractions of each step's tension scale (its largest
# segment tension, at least SNAP_FLOOR [N]): the largest change of a segment's tension in one
# step, and the largest impact of a slack segment (what tells a snap to the adaptive
# integrator: parting.check_segments, adaptive.py)
TENSION_CHANGE = 26
SLACK_IMPACT = 27
SNAP_FLOOR = 28
# state: 1 when the line's rows of the accelerations (System.accel) are its last step's, which
# the adaptive integrator's implicit step starts from (kernels.implicit_euler_run); else 0
HISTORY = 29
# state, since it was cleared: the largest change of a segment's tension in one step as
# TENSION_CHANGE, but as a fraction of a scale of at least CALM_FLOOR_FACTOR x SNAP_FLOOR
# (what tells the adaptive integrator that a line is calm again after a snap)
CALM_CHANGE = 30
# the strain-tension curve (tension_curve.py); none of it is state
CURVE_POINTS = 31
CURVE_CAPACITY = 32
CURVE_STRAIN = 32
CURVE_TENSION = CURVE_STRAIN + CURVE_CAPACITY
CURVE_SLOPE = CURVE_TENSION + CURVE_CAPACITY
LINE_REAL_COLUMNS = CURVE_SLOPE + CURVE_CAPACITY

NO_WINCH = 0
SPEED = 1
BRAKE = 2
CONSTANT_TENSION = 3

KIND = 0
OWN_MASS = 1
TOTAL_MASS = 2
VOLUME = 3
DRAG_AREA = 4
ADDED_MASS = 5
SIZE = 6
POINT_SINK = 7
POINT_BODY = 8
POINT_OFFSET = 9  # 3 entries
POINT_COLUMNS = 12

FIXED = 0
DRIVEN = 1
FREE = 2
CARRIED = 3  # a point a body carries (layout.BODY table): a fairlead on a free ship

BODY_POSITION = 0  # 3: state: its centre of gravity [m]
BODY_QUATERNION = 3  # 4: state: its orientation (x, y, z, w), body to world axes
BODY_VELOCITY = 7  # 3: state: its centre of gravity's velocity [m/s]
BODY_OMEGA = 10  # 3: state: its angular velocity, world axes [rad/s]
BODY_STATE = 13  # the state's columns: position, quaternion, velocity, angular velocity
BODY_ACCEL = 13  # 6: state: the accelerations of the last implicit step (Newmark's a0)
BODY_CLOCK = 19  # state: time since BODY_LOAD was set [s] (each step adds its own)
BODY_MASS = 20  # [kg]
BODY_INERTIA = 21  # 3: principal moments of inertia about the centre of gravity [kg m^2]
BODY_ADDED = 24  # 6: added mass: surge, sway, heave [kg], roll, pitch, yaw [kg m^2]
BODY_LINEAR_DAMPING = 30  # 6: [N per m/s], [N m per rad/s]
BODY_QUADRATIC_DAMPING = 36  # 6: [N per (m/s)^2], [N m per (rad/s)^2]
BODY_RESTORING = 42  # 3: hydrostatic heave [N/m], roll, pitch [N m/rad] stiffness
BODY_REST_Z = 45  # z of its body origin (on the waterplane) where it floats freely [m]
BODY_HULL = 46  # 3: the hull box the fenders touch: length, beam, draft [m]
BODY_ORIGIN = 49  # 3: its body origin (the hull box's centre in plan) from the CG, body axes
BODY_LOAD = 52  # 6: external force [N] and moment about the CG [N m], world axes, at clock 0
BODY_LOAD_RATE = 58  # 6: their change per second of the clock
# a hydrodynamic database's (model/ship/radiation.py): with BODY_FULL_ADDED 1 the added mass
# is BODY_ADDED_MATRIX, the full 6x6 A_inf about the centre of gravity in body axes (row-major),
# in place of BODY_ADDED's diagonal; BODY_MODES of the radiation memory's modes follow, each
# MODE_COLUMNS long from BODY_MODE (0 modes, 0 flag: no database, the constants above only)
BODY_FULL_ADDED = 64
BODY_ADDED_MATRIX = 65  # 36
BODY_MODES = 101  # the number of modes in use
BODY_MODE = 102  # the first mode's first column
MODE_POLE = 0  # 2: its pole lambda [1/s], real and imaginary part
MODE_WEIGHT = 2  # 1 for a real pole, 2 for one of a complex pair (its conjugate left out)
MODE_INPUT = 3  # 12: b, real parts (6) then imaginary parts (6): z' = lambda z + b . u
MODE_OUTPUT = 15  # 12: c likewise: the memory load (body axes) is weight Re(c z)
MODE_STATE = 27  # 2: state: z, real and imaginary part
MODE_COLUMNS = 29
MODE_CAPACITY = 48  # at most this many modes a body (radiation.MAX_MODES)
BODY_COLUMNS = BODY_MODE + MODE_CAPACITY * MODE_COLUMNS

FENDER_POSITION = 0  # 3: the centre of its face, uncompressed [m]
FENDER_NORMAL = 3  # 3: unit normal out of the quay, toward the ship
FENDER_FRICTION = 6  # friction coefficient against the hull
FENDER_BODY = 7  # the body row whose hull it touches
FENDER_POINTS = 8  # points of its curve (the first (0, 0))
FENDER_CAPACITY = 16
FENDER_CURVE_COMPRESSION = 9
FENDER_CURVE_REACTION = FENDER_CURVE_COMPRESSION + FENDER_CAPACITY
FENDER_COLUMNS = FENDER_CURVE_REACTION + FENDER_CAPACITY

# ENV array (ENV_COLUMNS,), float: what the lines live in (objects.Environment). A level of
# -inf means "none" (no water, no seabed); an all-zero quay normal means no quay.
ENV_GRAVITY = 0  # 3 entries: gravity vector [m/s^2]
ENV_WATER_LEVEL = 3  # z of the still water surface [m]
ENV_WATER_DENSITY = 4  # [kg/m^3]
ENV_AIR_DENSITY = 5  # [kg/m^3]
ENV_CURRENT = 6  # 3 entries: uniform current below the surface [m/s]
ENV_SEABED_LEVEL = 9  # z of the flat seabed [m]
ENV_SEABED_STIFFNESS = 10  # MoorDyn's kBot [Pa/m]
ENV_SEABED_DAMPING = 11  # MoorDyn's cBot [Pa s/m]
ENV_SEABED_FRICTION = 12  # Coulomb friction coefficient mu
ENV_QUAY_EDGE = 13  # 3 entries: a point on the top edge of the quay face (z: deck level)
ENV_QUAY_NORMAL = 16  # 3 entries: outward horizontal unit normal of the face (0: no quay)
ENV_QUAY_DEPTH = 19  # how far below the deck the quay block reaches [m]
ENV_COLUMNS = 20
