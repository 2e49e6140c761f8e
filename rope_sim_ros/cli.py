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

Subcommands: run (a motion table through the line, to CSV and/or a bag), resim (a bag's
inputs through the line with other parameters), plot and info (look at a bag), recover
(complete a bag whose recorder was killed). This module parses arguments and reports
errors; the work is done in runner, resim, plot and bag.

Bad input (files, parameters, bag paths) is one line on stderr and exit code 2, never a
traceback.
"""

import argparse
import sys
from typing import List, Optional

import yaml

from . import cli_arrangement as _arrangement
from .bag import BagError
from .model.materials import MaterialError
from .params.table import ParameterError, SPECS
from .trajectory import TrajectoryError

PROG = 'rope_sim'
EXIT_INPUT = 2
EXIT_OUTPUT = 1
EXIT_INTERRUPTED = 130
# Whatever a user can get wrong in a file or an argument: reported as one line, exit 2.
INPUT_ERRORS = (ParameterError, MaterialError, TrajectoryError, BagError)


def parse_set(items: Optional[List[str]]) -> dict:
    """
    Parse ``--set key=value`` items; values are YAML scalars or lists.

    A value YAML reads as a string but Python reads as a number (``1e-3``, which YAML 1.1
    leaves a string) becomes that number, unless the parameter is a string.

    :param items: the raw items.
    :returns: {key: value}, the last item winning.
    :raises ParameterError: an item is not key=value or its value is not YAML.
    """
    values = {}
    for item in items or []:
        key, sep, text = item.partition('=')
        key = key.strip()
        if not sep or not key:
            raise ParameterError(f'--set {item!r}: expected key=value, e.g. --set length=40')
        try:
            value = yaml.safe_load(text) if text.strip() else ''
        except yaml.YAMLError:
            raise ParameterError(
                f'--set {item!r}: {text!r} is not a YAML value') from None
        spec = SPECS.get(key)
        if spec is None or not isinstance(spec.default, str):
            value = _numbers(value)
        values[key] = value
    return values


def _numbers(value):
    if isinstance(value, list):
        return [_numbers(v) for v in value]
    if isinstance(value, str):
        try:
            return float(value)
        except ValueError:
            return value
    return value


def _add_params_options(parser: argparse.ArgumentParser, default: str) -> None:
    parser.add_argument(
        '--params', metavar='PARAMS.yaml',
        help=f'ROS parameter file (mooring_line: ros__parameters: ...); default: {default}')
    parser.add_argument(
        '--set', metavar='KEY=VALUE', action='append', default=[],
        help='override a parameter (repeatable), value as YAML: --set material=hmpe '
             '--set gravity=[0,0,-9.81]')


def build_parser() -> argparse.ArgumentParser:
    """Return the argument parser of rope_sim."""
    parser = argparse.ArgumentParser(
        prog=PROG, description='Offline mooring line simulation: run a motion, re-simulate, '
        'plot and inspect bags.')
    commands = parser.add_subparsers(dest='command', metavar='COMMAND', required=True)

    run = commands.add_parser(
        'run', help='run a motion table (MOTION.csv) through the line',
        description='Run the line through a motion table. MOTION.csv has a header with t, '
        'fairlead_x, fairlead_y, fairlead_z and optionally bollard_x, bollard_y, bollard_z '
        '(world-frame end points, interpolated between rows as the parameter '
        'end_interpolation says: cubic by default, linear = the secant of each row interval). '
        'Writes OUT.csv with the forces of the line on both ends every 1/rate s and/or a bag '
        'as the node records it.')
    _add_params_options(run, 'config/mooring_line.yaml')
    run.add_argument('--motion', required=True, metavar='MOTION.csv', help='motion table')
    run.add_argument('--out', metavar='OUT.csv',
                     help='output table (overwritten); required unless --bag is given')
    run.add_argument('--rate', type=float, default=100.0, metavar='HZ',
                     help='output rows per simulated second (default 100)')
    run.add_argument('--bag', metavar='DIR', help='also record a bag to this new directory')
    run.add_argument('--quiet', action='store_true', help='no progress bar or summary')

    resim = commands.add_parser(
        'resim', help="re-simulate a bag's inputs with other parameters",
        description='Feed the fairlead/bollard poses of BAG through a fresh line, as fast as '
        'possible, and write a new bag of the same layout. Deterministic: the same inputs '
        'and parameters give byte-identical messages.')
    resim.add_argument('bag', metavar='BAG', help='recorded bag directory (or .mcap file)')
    resim.add_argument('--out', required=True, metavar='NEWBAG', help='new bag directory')
    _add_params_options(resim, "the bag's stored parameters, else config/mooring_line.yaml")
    resim.add_argument('--rate', type=float, metavar='HZ',
                       help='output rate (default: that of the recorded rope/particles, '
                       'else 100)')
    resim.add_argument('--namespace', metavar='NS',
                       help='namespace of the line in the bag (default: the only one)')
    resim.add_argument('--quiet', action='store_true', help='no progress bar or summary')

    plot = commands.add_parser(
        'plot', help='plot tensions (with MBL and WLL) and rope shapes of a bag',
        description='Draw fairlead and bollard tension over time with the minimum breaking '
        'load and working load limit of the material, and a few rope shapes (x-z).')
    plot.add_argument('bag', metavar='BAG', help='bag directory (or .mcap file)')
    plot.add_argument('-o', '--output', required=True, metavar='FILE.png', help='image file')
    _add_params_options(plot, "the bag's stored parameters, else config/mooring_line.yaml")
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
    return parser


def _progress(quiet: bool):
    from .runner import Progress
    return None if quiet else Progress()


def _compiling_notice(quiet: bool):
    """Say on stderr when numba compiles the kernels (where the build left none: 1-3 min)."""
    from .precompile import announce_compilation
    return announce_compilation(
        None if quiet else lambda message: print(f'{PROG}: {message}', file=sys.stderr))


def _cmd_run(args) -> int:
    from .arrangement_runner import is_arrangement_file
    from .motion import read_motion
    from .runner import resolve_params, run_motion
    if args.out is None and args.bag is None:
        raise ParameterError('run: give --out OUT.csv and/or --bag DIR')
    if args.params is not None and is_arrangement_file(args.params):
        return _arrangement.run(args, parse_set(args.set), _progress, _compiling_notice)
    params = resolve_params(args.params, parse_set(args.set))
    motion = read_motion(args.motion)
    progress = _progress(args.quiet)
    try:
        with _compiling_notice(args.quiet):
            summary = run_motion(params, motion, args.out, args.rate, args.bag, progress)
    finally:
        if progress is not None:
            progress.finish()
    for t, distance in summary.beyond_reach:
        print(f'{PROG}: warning: {t:.3f} s into the run the ends were up to {distance:.4g} m '
              f"apart, beyond the line's reach of {summary.reach:.4g} m (length x (1 + "
              'max_strain)): the rope held the fairlead at the reach', file=sys.stderr)
    for t, reason in summary.restarts:
        print(f'{PROG}: warning: {t:.3f} s into the run the rope was restarted at rest on the '
              f'catenary: {reason}', file=sys.stderr)
    if summary.dropped:
        print(f'{PROG}: warning: {summary.dropped} bag messages were not recorded',
              file=sys.stderr)
    if not args.quiet:
        targets = ' and '.join(t for t in (args.out, args.bag) if t)
        print(f'{summary.rows} outputs, t = {summary.start:.3f} .. {summary.end:.3f} s every '
              f'{1 / args.rate:g} s (step {summary.time_step * 1e3:.4g} ms) -> {targets} '
              f'in {summary.wall:.1f} s')
    return 0


def _bag_params(args):
    from .resim import stored_parameters
    from .runner import resolve_params
    stored = None if args.params is not None else stored_parameters(args.bag)
    return resolve_params(args.params, parse_set(args.set), stored)


def _cmd_resim(args) -> int:
    from .resim import resim
    if _arrangement.is_arrangement(args):
        return _arrangement.resim(args, parse_set(args.set), _progress, _compiling_notice)
    params = _bag_params(args)
    progress = _progress(args.quiet)
    try:
        with _compiling_notice(args.quiet):
            result = resim(args.bag, args.out, params, args.rate, args.namespace, progress)
    finally:
        if progress is not None:
            progress.finish()
    for reason in result.skipped:
        print(f'{PROG}: warning: skipped input {reason}', file=sys.stderr)
    if result.run.dropped:
        print(f'{PROG}: warning: {result.run.dropped} bag messages were not recorded',
              file=sys.stderr)
    if not args.quiet:
        print(f'{result.run.rows} outputs at {result.rate:g} Hz, t = {result.run.start:.3f} .. '
              f'{result.run.end:.3f} s, {params.material} {params.diameter * 1e3:g} mm, '
              f'{params.length:g} m, N = {params.segments} -> {args.out} '
              f'in {result.run.wall:.1f} s')
    return 0


def _cmd_plot(args) -> int:
    from .plot import plot_bag
    if _arrangement.is_arrangement(args):
        return _arrangement.plot(args)
    if args.shapes < 0:
        raise ParameterError(f'--shapes {args.shapes}: must be >= 0')
    params = _bag_params(args)
    print(plot_bag(args.bag, args.output, params, args.namespace, args.shapes))
    return 0


def _cmd_info(args) -> int:
    from .plot import describe
    print(describe(args.bag))
    if _arrangement.is_arrangement(args):
        print(_arrangement.describe_lines(args.bag))
    return 0


def _cmd_recover(args) -> int:
    from .bag import bag_info, recover
    before = bag_info(args.bag)
    count = recover(args.bag, args.out)
    target = args.out or args.bag
    state = 'was complete already; rewritten' if before.complete else 'recovered'
    print(f'{target}: {state}: {count} messages in {len(before.files)} file(s)')
    for name, topic in sorted(bag_info(target).topics.items()):
        print(f'  {name}  {topic.type_name}  {topic.message_count}')
    return 0


COMMANDS = {
    'run': _cmd_run,
    'resim': _cmd_resim,
    'plot': _cmd_plot,
    'info': _cmd_info,
    'recover': _cmd_recover,
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
