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
rope_sim's commands on an arrangement (cli.py hands them over): run, resim, plot, info.

An arrangement's parameter file has a `mooring:` section; an arrangement's bag stores its
arrangement (the mooring node's, arrangement.PARAMETERS_KEY). With one, `run` takes
--motion SHIP.csv (the ship's poses, arrangement_runner.read_ship_motion), `resim` the
bag's ship poses, `plot` draws FILE.png (tensions) and FILE_plan.png (the berth from
above), and `info` adds every line's peak. Imports stay inside the functions: rope_sim
starts without numpy where it can.
"""

import os
import sys

PROG = 'rope_sim'


def is_arrangement(args) -> bool:
    """Tell whether the command is about an arrangement (its --params, else its bag)."""
    from .arrangement_plot import stored_arrangement
    from .arrangement_runner import is_arrangement_file
    if getattr(args, 'params', None) is not None:
        return is_arrangement_file(args.params)
    return stored_arrangement(args.bag) is not None


def _setup(args, overrides):
    from .arrangement_plot import stored_arrangement
    from .arrangement_runner import load_arrangement, with_overrides
    if getattr(args, 'params', None) is not None:
        return load_arrangement(args.params, overrides)
    return with_overrides(stored_arrangement(args.bag), overrides)


def _report(summary) -> None:
    for t, line, why in summary.restarts:
        print(f'{PROG}: warning: {t:.3f} s into the run {line} was restarted at rest: {why}',
              file=sys.stderr)
    for line, distance in summary.beyond_reach.items():
        print(f'{PROG}: warning: the ends of {line} were up to {distance:.4g} m apart, beyond '
              'its reach: its fairlead was held at the reach', file=sys.stderr)


def run(args, overrides, progress_factory, notice_factory) -> int:
    """`rope_sim run --params ARRANGEMENT.yaml --motion SHIP.csv`."""
    from .arrangement_runner import read_ship_motion, run_ship_motion
    setup = _setup(args, overrides)
    ship = read_ship_motion(args.motion)
    progress = progress_factory(args.quiet)
    try:
        with notice_factory(args.quiet):
            summary = run_ship_motion(setup, ship, args.out, args.rate, args.bag, progress)
    finally:
        if progress is not None:
            progress.finish()
    _report(summary)
    if not args.quiet:
        targets = ' and '.join(t for t in (args.out, args.bag) if t)
        print(f'{summary.rows} outputs of {len(setup.lines)} lines, t = {summary.start:.3f} .. '
              f'{summary.end:.3f} s every {1 / args.rate:g} s -> {targets} in '
              f'{summary.wall:.1f} s')
    return 0


def resim(args, overrides, progress_factory, notice_factory) -> int:
    """`rope_sim resim BAG --out NEWBAG` of a mooring node's bag."""
    from .arrangement_runner import resim as resim_bag
    setup = _setup(args, overrides)
    progress = progress_factory(args.quiet)
    try:
        with notice_factory(args.quiet):
            summary, rate = resim_bag(args.bag, args.out, setup, args.rate, progress)
    finally:
        if progress is not None:
            progress.finish()
    _report(summary)
    if not args.quiet:
        print(f'{summary.rows} outputs of {len(setup.lines)} lines at {rate:g} Hz, t = '
              f'{summary.start:.3f} .. {summary.end:.3f} s -> {args.out} in '
              f'{summary.wall:.1f} s')
    return 0


def plot(args) -> int:
    """`rope_sim plot BAG -o FILE.png`: FILE.png (tensions) and FILE_plan.png."""
    from .arrangement_plot import plot_record
    folder, name = os.path.split(os.path.abspath(args.output))
    stem = os.path.splitext(name)[0]
    for path in plot_record(args.bag, folder, tensions=name, plan=f'{stem}_plan.png'):
        print(path)
    return 0


def describe_lines(bag) -> str:
    """Return every line's peak tension and utilisation (for `rope_sim info`)."""
    from .arrangement_runner import describe_lines as describe
    return describe(bag)
