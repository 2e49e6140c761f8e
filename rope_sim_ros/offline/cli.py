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
``rope_sim``: the offline command line (also ``python -m rope_sim_ros``).

Subcommands: run (a motion through a line or an arrangement, to CSV and/or a bag), resim (a
bag's inputs with other parameters), plot and info (look at a bag), recover (complete a bag
whose recorder was killed), study, stiffness, berth-check and hydro (a ship's hydrodynamic
database). A parameter file with `lines` for the mooring node is an
arrangement, and its motion is the ship's (SHIP.csv); any other is a single line's
(mooring_line: ros__parameters:), and its motion the fairlead's (MOTION.csv). A bag says
itself which it is (the parameters it stores). This module parses arguments and reports
errors; the work is done in run, resim, plot and bag.

Bad input (files, parameters, bag paths) is one line on stderr and exit code 2, never a
traceback. Imports stay inside the commands: rope_sim starts without numpy where it can.
"""

import argparse
import os
import sys
from typing import List, Optional

from ..bag import BagError
from ..model.materials import MaterialError
from ..model.statics.pretension import PretensionError
from ..mooring.trajectory import TrajectoryError
from ..params.table import ParameterError

PROG = 'rope_sim'
EXIT_INPUT = 2
EXIT_OUTPUT = 1
EXIT_INTERRUPTED = 130
# Whatever a user can get wrong in a file or an argument: reported as one line, exit 2.
INPUT_ERRORS = (ParameterError, MaterialError, TrajectoryError, BagError, PretensionError)
LINE_FILE = 'config/mooring_line.yaml'


def _add_params_options(parser: argparse.ArgumentParser, default: str) -> None:
    parser.add_argument(
        '--params', metavar='PARAMS.yaml',
        help='ROS parameter file: a single line (mooring_line: ros__parameters: ...) or an '
             f'arrangement (mooring: ros__parameters: lines: ...); default: {default}')
    parser.add_argument(
        '--set', metavar='KEY=VALUE', action='append', default=[],
        help='override a parameter (repeatable), value as YAML: --set material=hmpe '
             '--set gravity=[0,0,-9.81]; a line of an arrangement: --set head_1.length=40')


def build_parser() -> argparse.ArgumentParser:
    """Return the argument parser of rope_sim."""
    parser = argparse.ArgumentParser(
        prog=PROG, description='Offline mooring simulation: run a motion, re-simulate, plot '
        'and inspect bags.')
    commands = parser.add_subparsers(dest='command', metavar='COMMAND', required=True)

    run = commands.add_parser(
        'run', help='run a motion table through a line (MOTION.csv) or an arrangement '
        '(SHIP.csv)',
        description='Run a motion through the mooring. For a single line, MOTION.csv has a '
        'header with t, fairlead_x, fairlead_y, fairlead_z and optionally bollard_x, '
        'bollard_y, bollard_z (world-frame end points, interpolated between rows as the '
        'parameter end_interpolation says: cubic by default, linear = the secant of each row '
        'interval) and winch_speed. For an arrangement, SHIP.csv has t, x, y, z and qx, qy, '
        'qz, qw or yaw. A free ship (ship_mode: free) takes no motion: it starts at rest at '
        'its start pose and runs for --duration s under the loads of --loads LOADS.csv (t, '
        'force_x, force_y, force_z, moment_x, moment_y, moment_z: frame_id axes, about its '
        'origin, linear between rows). Either takes line-handling commands from --commands '
        'COMMANDS.csv (t, line, command and optionally bollard: make_fast, let_go, stow or '
        "let_go_all at t s from the run's start). Writes OUT.csv with the forces and states "
        "of the lines every 1/rate s (and a free ship's motion and fenders) and/or a bag as "
        'the node records it.')
    _add_params_options(run, LINE_FILE)
    run.add_argument('--motion', metavar='MOTION.csv',
                     help='motion table (SHIP.csv for an arrangement); not for a free ship')
    run.add_argument('--loads', metavar='LOADS.csv',
                     help="a free ship's external load over time (default: none)")
    run.add_argument('--duration', type=float, metavar='S',
                     help="a free ship's run: how many simulated seconds")
    run.add_argument('--commands', metavar='COMMANDS.csv',
                     help='line-handling commands at their times: t, line, command (make_fast, '
                     'let_go, stow, let_go_all) and optionally bollard (default: none)')
    run.add_argument('--out', metavar='OUT.csv',
                     help='output table (overwritten); required unless --bag is given')
    run.add_argument('--rate', type=float, default=100.0, metavar='HZ',
                     help='output rows per simulated second (default 100)')
    run.add_argument('--bag', metavar='DIR', help='also record a bag to this new directory')
    run.add_argument('--quiet', action='store_true', help='no progress bar or summary')

    resim = commands.add_parser(
        'resim', help="re-simulate a bag's inputs with other parameters",
        description="Feed a bag's poses (a line's fairlead and bollard poses, or a ship's) "
        'through a fresh mooring, as fast as possible, and write a new bag of the same '
        "layout. A node's recording is replayed with its decisions (its events). "
        'Deterministic: the same inputs and parameters give byte-identical messages.')
    resim.add_argument('bag', metavar='BAG', help='recorded bag directory (or .mcap file)')
    resim.add_argument('--out', required=True, metavar='NEWBAG', help='new bag directory')
    _add_params_options(resim, f"the bag's stored parameters, else {LINE_FILE}")
    resim.add_argument('--rate', type=float, metavar='HZ',
                       help='output rate (default: that of the recorded rope/particles, '
                       'else 100)')
    resim.add_argument('--namespace', metavar='NS',
                       help='namespace of the mooring in the bag (default: the only one)')
    resim.add_argument('--quiet', action='store_true', help='no progress bar or summary')

    plot = commands.add_parser(
        'plot', help='plot tensions (with MBL and WLL), rope shapes or the berth of a bag',
        description="A line's bag: fairlead and bollard tension over time with the minimum "
        'breaking load and working load limit of the material, and a few rope shapes (x-z). '
        "An arrangement's bag: FILE.png (every line's tension and the ship's motion) and "
        'FILE_plan.png (the berth from above at its most loaded moment).')
    plot.add_argument('bag', metavar='BAG', help='bag directory (or .mcap file)')
    plot.add_argument('-o', '--output', required=True, metavar='FILE.png', help='image file')
    _add_params_options(plot, f"the bag's stored parameters, else {LINE_FILE}")
    plot.add_argument('--namespace', metavar='NS',
                      help='namespace of the line in the bag (default: the only one)')
    plot.add_argument('--shapes', type=int, default=5, metavar='N',
                      help='rope shapes to draw (default 5)')

    info = commands.add_parser(
        'info', help='topics, counts, duration and peak tensions of a bag')
    info.add_argument('bag', metavar='BAG', help='bag directory (or .mcap file)')

    recover = commands.add_parser(
        'recover', help='complete a bag whose recorder was killed',
        description='Rewrite everything readable (all finished chunks) of a bag cut short by '
        'a kill as a complete bag, in place or into a new directory.')
    recover.add_argument('bag', metavar='BAG', help='bag directory (or .mcap file)')
    recover.add_argument('--out', metavar='NEWBAG',
                         help='write the recovered bag here instead of in place')

    study = commands.add_parser(
        'study', help='run the cases of a study (STUDY.yaml) on Dask: results, plots',
        description='Run every case of a study: an arrangement with factors varied (any '
        "parameter --set takes, a motion file per case), each case a run of the study's "
        'duration, on a local cluster of one process per core or on the workers of a Dask '
        'scheduler. Writes DIR/results.csv and DIR/results.parquet (one row per case), '
        "DIR/utilisation.png, DIR/heatmap.png and each case's files in DIR/cases/. Started "
        'again, runs only the cases not done yet.')
    study.add_argument('study', metavar='STUDY.yaml', help='the study file')
    study.add_argument('--out', required=True, metavar='DIR', help="the study's folder")
    study.add_argument('--workers', type=int, metavar='N',
                       help='local cluster processes, one thread each (default: one per core)')
    study.add_argument('--scheduler', metavar='tcp://HOST:PORT',
                       help="run on this Dask scheduler's workers instead of a local cluster")
    study.add_argument('--dry-run', action='store_true',
                       help='list the cases (and which are done) and run nothing')
    study.add_argument('--quiet', action='store_true', help='no progress bar or summary')

    stiffness = commands.add_parser(
        'stiffness', help="the 6x6 stiffness of the lines and fenders at the ship's start pose",
        description="Print the stiffness matrix of an arrangement's lines and fenders (the "
        "quasi-static elastic catenaries, pretensions resolved) about the ship's origin at its "
        'start pose (ship.start_position, ship.start_yaw), in frame_id axes: its last six '
        'lines, six numbers each, rows and columns x, y, z, roll, pitch, yaw (N/m, N/rad, '
        'N m/m, N m/rad).')
    _add_params_options(stiffness, LINE_FILE)
    stiffness.add_argument('--hydrostatics', action='store_true',
                           help="add the ship's heave, roll and pitch restoring")

    berth = commands.add_parser(
        'berth-check', help='will the arrangement hold its ship in this wind and current?',
        description="The ship's quasi-static equilibrium under its lines and fenders with "
        'the wind from every direction (from the bow toward port) at one speed and each '
        "current of the scenario; prints and plots, per direction, the most loaded line's "
        "share of its MBL against its WLL, the ship's offset and the fender loads. By "
        "default OCIMF MEG4's standard criteria: a 60 knot wind with a current of 3 knots "
        'from ahead or astern, 2 knots at 10 or 170 degrees, or 0.75 knots from the beam. '
        'Writes DIR/berth_check.csv and DIR/berth_check.png.')
    berth.add_argument('arrangement', metavar='ARRANGEMENT.yaml', help="the mooring node's "
                       'parameter file (lines, ship, fenders)')
    berth.add_argument('--wind-speed', type=float, metavar='V',
                       help='wind speed [m/s] (default 30.87: 60 knots)')
    berth.add_argument('--current', metavar='X,Y,Z',
                       help="one current instead of MEG4's: the water's velocity in "
                       'frame_id [m/s]')
    berth.add_argument('--directions', type=int, default=24, metavar='N',
                       help='wind directions, evenly spaced (default 24: every 15 degrees)')
    berth.add_argument('--out', default='berth_check', metavar='DIR',
                       help='folder for berth_check.csv and .png (default ./berth_check)')
    berth.add_argument('--set', action='append', default=[], metavar='NAME=VALUE',
                       help='override a parameter (repeatable)')
    berth.add_argument('--quiet', action='store_true', help='print only the file names')

    hydro = commands.add_parser(
        'hydro', help="the ship's hydrodynamic database (added mass, damping, wave loads) "
        'from Capytaine',
        description="Solve the arrangement's ship with Capytaine's boundary-element method "
        'at its water depth, density and gravity: added mass and radiation damping per '
        'frequency and at infinite frequency, the wave excitation (Froude-Krylov and '
        'diffraction) per heading and the mean drift in surge, sway and yaw, all about the '
        'centre of gravity (ship.center_of_gravity). The hull is ship.mesh, else a '
        'parametric hull of ship.length, beam, draft and block_coefficient. Writes SHIP.nc '
        "(Capytaine's NetCDF dataset; docs/waves.md).")
    hydro.add_argument('arrangement', metavar='ARRANGEMENT.yaml', help="the mooring node's "
                       'parameter file (the ship and the water)')
    hydro.add_argument('--out', required=True, metavar='SHIP.nc', help='the database file')
    hydro.add_argument('--force', action='store_true', help='overwrite an existing SHIP.nc')
    hydro.add_argument('--set', action='append', default=[], metavar='NAME=VALUE',
                       help='override a parameter (repeatable): --set ship.draft=12')
    hydro.add_argument('--omega', nargs=3, type=float, metavar=('MIN', 'MAX', 'N'),
                       help='N wave frequencies from MIN to MAX rad/s (default 0.05 2.0 40)')
    hydro.add_argument('--heading-step', type=float, default=30.0, metavar='DEG',
                       help='headings every DEG degrees round the circle (default 30)')
    hydro.add_argument('--panel-size', type=float, default=3.0, metavar='M',
                       help="the parametric hull's panel size [m] (default 3)")
    hydro.add_argument('--no-lid', action='store_true',
                       help='no lid at the waterline (the lid removes the irregular '
                       'frequencies)')
    hydro.add_argument('--quiet', action='store_true', help='no progress bar or summary')
    return parser


def _progress(quiet: bool):
    from .progress import Progress
    return None if quiet else Progress()


def _compiling_notice(quiet: bool):
    """Say on stderr when numba compiles the kernels (where the build left none: 1-3 min)."""
    from ..mooring.precompile import announce_compilation
    return announce_compilation(
        None if quiet else lambda message: print(f'{PROG}: {message}', file=sys.stderr))


def _setup(args, bag: Optional[str] = None):
    """
    Return the parameters of a command: --params, else those a bag stores, else the default.

    --set overrides them all.
    """
    from ..params.arrangement import read_setup
    from ..params.files import parse_set
    from ..params.materials import default_config_dir
    overrides = parse_set(args.set)
    if args.params is None and bag is not None:
        from .resim import stored_setup
        stored = stored_setup(bag, overrides)
        if stored is not None:
            return stored
    path = args.params
    if path is None:
        default = os.path.join(default_config_dir(), 'mooring_line.yaml')
        path = default if os.path.exists(default) else None
    return read_setup(path, overrides)


def _report(summary, single: bool) -> None:
    for t, line, distance in summary.beyond_reach:
        whose = "the line's" if single else f"{line}'s"
        print(f'{PROG}: warning: {t:.3f} s into the run the ends of {line or "the line"} '
              f'were up to {distance:.4g} m apart, beyond {whose} reach of '
              f'{summary.reach[line]:.4g} m (length x (1 + max_strain)): the rope held the '
              'fairlead at the reach', file=sys.stderr)
    for t, line, reason in summary.restarts:
        print(f'{PROG}: warning: {t:.3f} s into the run {line or "the rope"} was restarted '
              f'at rest: {reason}', file=sys.stderr)
    if summary.dropped:
        print(f'{PROG}: warning: {summary.dropped} bag messages were not recorded',
              file=sys.stderr)


def _commands(args, setup):
    """Return the commands of --commands (none without it), checked against the mooring."""
    from .motion import read_commands
    if args.commands is None:
        return ()
    return read_commands(args.commands, setup.names,
                         [bollard.name for bollard in setup.bollards]).commands


def _say_events(quiet: bool, progress):
    """
    Return the event sink that prints each line event once, as the run goes.

    As the node logs them: a command taken on stdout (not with --quiet), a refused one and a
    quick-release hook's release as warnings on stderr.
    """
    def say(event) -> None:
        if progress is not None:
            progress.clear()
        if event.refused:
            print(f'{PROG}: warning: t = {event.t:.3f} s: {event.command} refused: '
                  f'{event.text}', file=sys.stderr, flush=True)
        elif event.kind == 'released':
            print(f'{PROG}: warning: t = {event.t:.3f} s: {event.text}', file=sys.stderr,
                  flush=True)
        elif not quiet:
            print(f'{PROG}: t = {event.t:.3f} s: {event.text}', flush=True)
    return say


def _report_not_taken(summary, origin: float) -> None:
    if summary.not_taken:
        count, first = len(summary.not_taken), summary.not_taken[0]
        print(f'{PROG}: warning: {count} command{"s" if count > 1 else ""} from t = '
              f'{first.t:g} s on {"were" if count > 1 else "was"} not taken: the run ended at '
              f'{summary.end - origin:.3f} s', file=sys.stderr)


def _cmd_run(args) -> int:
    from .motion import read_motion, read_ship_motion
    from .run import run_motion
    if args.out is None and args.bag is None:
        raise ParameterError('run: give --out OUT.csv and/or --bag DIR')
    setup = _setup(args)
    if setup.ship.free:
        return _run_free(args, setup)
    if args.motion is None:
        raise ParameterError('run: give --motion MOTION.csv (SHIP.csv for an arrangement), or '
                             'set ship_mode: free for a ship moved by its loads')
    if args.loads is not None or args.duration is not None:
        raise ParameterError('run: --loads and --duration are for a free ship (ship_mode: '
                             'free); a driven ship follows --motion')
    if setup.single:
        line = setup.lines[0].params
        streams = read_motion(args.motion, line.fairlead_offset, line.bollard_offset)
    else:
        streams = read_ship_motion(args.motion)
    commands = _commands(args, setup)
    progress = _progress(args.quiet)
    try:
        with _compiling_notice(args.quiet):
            summary = run_motion(setup, streams, args.out, args.rate, args.bag, progress,
                                 commands=commands, events=[_say_events(args.quiet, progress)])
    finally:
        if progress is not None:
            progress.finish()
    _report(summary, setup.single)
    _report_not_taken(summary, streams.origin)
    if not args.quiet:
        targets = ' and '.join(t for t in (args.out, args.bag) if t)
        what = '' if setup.single else f' of {len(setup.lines)} lines'
        print(f'{summary.rows} outputs{what}, t = {summary.start:.3f} .. {summary.end:.3f} s '
              f'every {1 / args.rate:g} s (step {summary.time_step * 1e3:.4g} ms) -> '
              f'{targets} in {summary.wall:.1f} s')
    return 0


def _run_free(args, setup) -> int:
    """rope_sim run of a free ship: --duration s from rest under --loads."""
    from .motion import read_loads
    from .run import run_free
    from ..mooring.ship import damping_advice
    if args.motion is not None:
        raise ParameterError('run: a free ship (ship_mode: free) takes no --motion: give '
                             '--duration S and optionally --loads LOADS.csv')
    if args.duration is None:
        raise ParameterError('run: a free ship (ship_mode: free) needs --duration S')
    if args.bag is not None:
        raise ParameterError("run: a free ship's run writes --out OUT.csv; record a bag "
                             'with the mooring node')
    loads = read_loads(args.loads) if args.loads is not None else None
    advice = damping_advice(setup)
    if advice:
        print(f'{PROG}: warning: {advice}', file=sys.stderr)
    commands = _commands(args, setup)
    progress = _progress(args.quiet)
    try:
        with _compiling_notice(args.quiet):
            summary = run_free(setup, args.duration, loads, args.out, args.rate, progress,
                               commands=commands, events=[_say_events(args.quiet, progress)])
    finally:
        if progress is not None:
            progress.finish()
    _report(summary, False)
    _report_not_taken(summary, 0.0)
    if not args.quiet:
        print(f'{summary.rows} outputs of a free ship on {len(setup.lines)} lines, t = '
              f'{summary.start:.3f} .. {summary.end:.3f} s every {1 / args.rate:g} s (step '
              f'{summary.time_step * 1e3:.4g} ms) -> {args.out} in {summary.wall:.1f} s')
    return 0


def _cmd_resim(args) -> int:
    from .resim import resim
    setup = _setup(args, args.bag)
    progress = _progress(args.quiet)
    try:
        with _compiling_notice(args.quiet):
            result = resim(args.bag, args.out, setup, args.rate, args.namespace, progress)
    finally:
        if progress is not None:
            progress.finish()
    for reason in result.skipped:
        print(f'{PROG}: warning: skipped input {reason}', file=sys.stderr)
    _report(result.run, setup.single)
    if not args.quiet:
        if setup.single:
            line = setup.lines[0].params
            what = (f'{line.material} {line.diameter * 1e3:g} mm, {line.length:g} m, '
                    f'N = {line.segments}')
        else:
            what = f'{len(setup.lines)} lines'
        print(f'{result.run.rows} outputs at {result.rate:g} Hz, t = {result.run.start:.3f} .. '
              f'{result.run.end:.3f} s, {what} -> {args.out} in {result.run.wall:.1f} s')
    return 0


def _cmd_plot(args) -> int:
    from .plot import plot_bag, plot_record
    if args.shapes < 0:
        raise ParameterError(f'--shapes {args.shapes}: must be >= 0')
    setup = _setup(args, args.bag)
    if setup.single:
        print(plot_bag(args.bag, args.output, setup.lines[0].params, args.namespace,
                       args.shapes))
        return 0
    folder, name = os.path.split(os.path.abspath(args.output))
    stem = os.path.splitext(name)[0]
    for path in plot_record(args.bag, folder, tensions=name, plan=f'{stem}_plan.png',
                            setup=setup, event=f'{stem}_event.png'):
        print(path)
    return 0


def _cmd_info(args) -> int:
    from .plot import describe, describe_lines
    from .resim import stored_setup
    print(describe(args.bag))
    setup = stored_setup(args.bag)
    if setup is not None and not setup.single:
        print(describe_lines(args.bag))
    return 0


def _cmd_recover(args) -> int:
    from ..bag import bag_info, recover
    before = bag_info(args.bag)
    count = recover(args.bag, args.out)
    target = args.out or args.bag
    state = 'was complete already; rewritten' if before.complete else 'recovered'
    print(f'{target}: {state}: {count} messages in {len(before.files)} file(s)')
    for name, topic in sorted(bag_info(target).topics.items()):
        print(f'  {name}  {topic.type_name}  {topic.message_count}')
    return 0


def _cmd_study(args) -> int:
    if args.workers is not None and args.scheduler is not None:
        raise ParameterError('study: give --workers (a local cluster) or --scheduler (its '
                             'workers), not both')
    try:
        import distributed  # noqa: F401
    except ImportError as e:
        print(f'{PROG} study: error: needs dask and distributed ({e}): pip install '
              '"dask[distributed]"', file=sys.stderr)
        return EXIT_OUTPUT
    from .study import run_study, StudyInterrupted, summary_lines

    def say(text: str) -> None:
        if not args.quiet:
            print(text, flush=True)

    try:
        report = run_study(args.study, args.out, args.workers, args.scheduler, args.dry_run,
                           say, progress=not args.quiet)
    except StudyInterrupted as e:
        done, total = e.report.done_before + e.report.ran, e.report.cases
        print(f'{PROG} study: interrupted: {done} of {total} cases done (in {args.out}); run '
              f'the same command again to run the other {total - done}', file=sys.stderr)
        return EXIT_INTERRUPTED
    if not args.dry_run:
        for line in summary_lines(report):
            say(line)
    return EXIT_OUTPUT if report.lost else 0


def _cmd_berth_check(args) -> int:
    from .berth_check import MEG4_WIND, parse_current, run
    from ..params.arrangement import is_arrangement_file, read_setup
    from ..params.files import parse_set
    if not is_arrangement_file(args.arrangement):
        raise ParameterError(f'berth-check: {args.arrangement} is not an arrangement (a '
                             "parameter file for the mooring node, with 'lines')")
    setup = read_setup(args.arrangement, parse_set(args.set))
    current = None if args.current is None else parse_current(args.current)
    wind = MEG4_WIND if args.wind_speed is None else args.wind_speed
    cases, lines = run(setup, args.out, wind, current, args.directions)
    if not args.quiet:
        print('\n'.join(lines))
    failed = sum(case.status != 'ok' for case in cases)
    if failed:
        print(f'{PROG}: warning: {failed} of {len(cases)} cases found no equilibrium (their '
              'status in berth_check.csv)', file=sys.stderr)
    print(f'-> {os.path.join(args.out, "berth_check.csv")}, '
          f'{os.path.join(args.out, "berth_check.png")}')
    return 0


def _cmd_stiffness(args) -> int:
    from .stiffness import stiffness_report
    print('\n'.join(stiffness_report(_setup(args), hydrostatics=args.hydrostatics)))
    return 0


def _cmd_hydro(args) -> int:
    import time
    from .hydro import default_settings, make_database, OMEGA_COUNT, OMEGA_MAX, OMEGA_MIN
    from ..params.files import parse_set
    low, high, count = args.omega if args.omega else (OMEGA_MIN, OMEGA_MAX, OMEGA_COUNT)
    if count != int(count):
        raise ParameterError(f'hydro: --omega N = {count:g}: must be a whole number')
    settings = default_settings(low, high, int(count), args.heading_step, args.panel_size,
                                not args.no_lid)
    progress = _progress(args.quiet)
    start = time.monotonic()
    try:
        dataset = make_database(args.arrangement, args.out, parse_set(args.set), settings,
                                args.force, None if progress is None else progress.show)
    finally:
        if progress is not None:
            progress.finish()
    if not args.quiet:
        print(f'{dataset.sizes["omega"]} frequencies x {dataset.sizes["wave_direction"]} '
              f'headings, {dataset.attrs["mesh_faces"]} panels -> {args.out} in '
              f'{time.monotonic() - start:.1f} s')
    return 0


COMMANDS = {
    'run': _cmd_run,
    'resim': _cmd_resim,
    'plot': _cmd_plot,
    'info': _cmd_info,
    'recover': _cmd_recover,
    'study': _cmd_study,
    'stiffness': _cmd_stiffness,
    'berth-check': _cmd_berth_check,
    'hydro': _cmd_hydro,
}


def main(argv: Optional[List[str]] = None) -> int:
    """
    Run rope_sim with the given arguments (default: sys.argv[1:]).

    :param argv: the arguments after the program name.
    :returns: the exit code: 0 success, 2 bad input (one line on stderr), 1 an output
        could not be written, 130 interrupted.
    """
    from .motion import MotionError
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as e:
        return int(e.code or 0) if not isinstance(e.code, str) else EXIT_INPUT
    try:
        return COMMANDS[args.command](args)
    except (MotionError, *INPUT_ERRORS) as e:
        print(f'{PROG} {args.command}: error: {e}', file=sys.stderr)
        return EXIT_INPUT
    except OSError as e:
        where = f'{e.filename}: ' if e.filename else ''
        print(f'{PROG} {args.command}: error: {where}{e.strerror or e}', file=sys.stderr)
        return EXIT_OUTPUT
    except KeyboardInterrupt:
        print(f'{PROG} {args.command}: interrupted; files hold what was done so far',
              file=sys.stderr)
        return EXIT_INTERRUPTED


if __name__ == '__main__':
    sys.exit(main())
