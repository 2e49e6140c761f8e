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
`make demo`: a berthing, then a ship passing the moored ship; recorded, plotted.

Starts, in their own ROS domain (unless ROS_DOMAIN_ID is set), the colcon-installed mooring
node with config/berth.yaml (a 225 m bulk carrier, eight lines, four fenders) and, on top,
config/berth_demo.yaml (the ship free, ship_mode: free, 30 m off her berth, parallel to it,
at rest, every line stowed; a 200 m ship passing 100 m off her berth at 2.5 m/s), use_sim_time,
recording to a new bag out/demo_<time>/bag; and the berth demo (ros/berth_demo_node.py:
/clock, sim time running at --speed times the wall clock; the pilot, whose tugs push her in
and land her on the fenders at 0.1 m/s; the crew, who make the lines fast and heave them to
their pretensions as config/berth_demo.yaml's schedule says; and the live table, one row a
simulated second: her distance off the fenders, her speed towards them, the tugs' push,
each fender's load, each line's state and tension, and where the passing ship is). The berth
demo ends by itself after --duration simulated seconds (by default berth_demo.duration, else
twice the time the passing ship takes to come abeam); then the mooring node is stopped with
SIGINT, by its process id, `rope_sim info` describes the bag, and the plots are drawn
(plot.py): out/demo_<time>/event.png, the loads on the ship (the tugs', the fenders', the
passing ship's), her motion and every line's tension on one time axis, each command marked,
and plan.png, the berth from above at the most loaded moment.

    python -m rope_sim_ros.offline.demo [--speed 2] [--duration S] [--install install]
        [--params config/berth.yaml] [--scenario config/berth_demo.yaml] [--out out]
"""

import argparse
import errno
import math
import os
from pathlib import Path
import signal
import subprocess
import sys
import time
from typing import Optional

import numpy as np

from .plot import abeam_time
from ..mooring.berthing import Berthing, read_berthing, watch
from ..mooring.ship import quay_normal, ship_loads, start_pose, water_depth
from ..params.arrangement import ArrangementParams, flatten, NODE_NAME, read_setup
from ..params.files import read_params_file
from ..params.table import not_positive, ParameterError

REPO = Path(__file__).resolve().parents[2]
PACKAGE = 'rope_sim_ros'
STOP_TIMEOUT = 10.0
MAX_SAFE_DOMAIN_ID = 101  # DDS ports of higher ids can collide with ephemeral ports
QUIET_DURATION = 60.0  # [s] simulated, without a passing ship coming abeam


def overlay_environment(prefix: Path) -> dict:
    """Return os.environ as `source install/setup.bash` would leave it for this package."""
    env = dict(os.environ)
    site = prefix / 'lib' / f'python{sys.version_info[0]}.{sys.version_info[1]}' / 'site-packages'
    ament = [str(prefix)] + [p for p in env.get('AMENT_PREFIX_PATH', '').split(os.pathsep)
                             if p and p != str(prefix)]
    if sys.prefix not in ament:
        ament.append(sys.prefix)  # the ROS wheels' share/ (message packages)
    env['AMENT_PREFIX_PATH'] = os.pathsep.join(ament)
    env['PYTHONPATH'] = os.pathsep.join(
        [str(site)] + [p for p in env.get('PYTHONPATH', '').split(os.pathsep) if p])
    env.setdefault('ROS_DOMAIN_ID', str(os.getpid() % MAX_SAFE_DOMAIN_ID + 1))
    env.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    env['PYTHONUNBUFFERED'] = '1'
    return env


def stop(children: dict) -> dict:
    """Send SIGINT to every running child (by pid), wait, and return the exit codes."""
    for child in reversed(list(children.values())):
        if child.poll() is None:
            os.kill(child.pid, signal.SIGINT)
    codes = {}
    deadline = time.monotonic() + STOP_TIMEOUT
    for name, child in children.items():
        try:
            codes[name] = child.wait(max(0.1, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            print(f'demo: {name} (pid {child.pid}) ignored SIGINT; killing it', file=sys.stderr)
            child.kill()
            codes[name] = child.wait()
    return codes


def demo_setup(params: Path, scenario: Optional[Path]) -> ArrangementParams:
    """
    Read the mooring node's parameters as it reads its two files: the scenario on top.

    :raises ParameterError: an unreadable file or a bad value; a ship that is not free.
    """
    if read_setup(params).single:
        raise ParameterError(f'{params} holds no mooring node parameters (mooring: '
                             'ros__parameters: lines: ...)')
    overrides = {} if scenario is None else flatten(read_params_file(scenario, NODE_NAME))
    setup = read_setup(params, overrides)
    if not setup.ship.free:
        raise ParameterError(f"ship_mode is '{setup.ship.mode}': the demo's ship moves by "
                             'itself: set ship_mode: free')
    return setup


def default_duration(setup: ArrangementParams, plan: Berthing = Berthing()) -> float:
    """Return the simulated seconds of the demo: its own, else the passing ship abeam midway."""
    if plan.duration is not None:
        return plan.duration
    when = abeam_time(setup.passing)
    return QUIET_DURATION if when is None else max(2.0 * when, 10.0)


def story(setup: ArrangementParams, plan: Berthing = Berthing()) -> str:
    """Return what the run is, a sentence for the top of event.png."""
    passing = setup.passing
    berthing, off = '', 0.0
    if any(order.kind == 'tugs' for order in plan.orders):
        off = watch(setup, *start_pose(setup), np.zeros(3))[0]
        fast = {order.line for order in plan.orders if order.what == 'make_fast'}
        berthing = (f'Tugs push the {setup.ship.length:g} m ship in from {off:.0f} m off and '
                    f'land her on her fenders at {plan.pilot.landing_speed:g} m/s; the crew '
                    f'makes {len(fast)} lines fast and heaves them to their pretensions')
    if not passing.present:
        return berthing or 'The free ship at its berth, no ship passing'
    when = abeam_time(passing)
    side = 'starboard' if passing.separation > 0.0 else 'port'
    depth = water_depth(setup.shared)
    return ((f'{berthing}; then a' if berthing else 'A')
            + f' {passing.length:g} m ship passes {passing_off(setup, off):.0f} m off the '
            f'{side} side at {passing.speed:g} m/s ({passing.speed * 3600 / 1852:.1f} kn)'
            + ('' if depth == math.inf else f' in {depth:g} m of water')
            + ('' if when is None else f', abeam at t = {when:.0f} s')
            + ('' if berthing else ': it moves the free ship, the lines hold it'))


def passing_off(setup: ArrangementParams, off: float = 0.0) -> float:
    """
    Return how far the passing ship's track is from the moored ship's centreline [m].

    Where she lies once moved `off` m towards her quay from her start pose (0: there).
    """
    passer = ship_loads(setup).passing
    where = np.asarray(setup.ship.start_position, dtype=float)
    if off:
        where = where - off * quay_normal(setup)
    apart = where - passer.midship(0.0)
    return float(abs(passer.heading[0] * apart[1] - passer.heading[1] * apart[0]))


def main(argv=None) -> int:
    """Run the demo; return the exit code (0 when every step went through)."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--speed', type=float, default=2.0,
                        help='simulated seconds per wall second (default 2)')
    parser.add_argument('--duration', type=float, default=None,
                        help='simulated seconds (default: twice the time the passing ship '
                        'takes to come abeam)')
    parser.add_argument('--install', type=Path, default=REPO / 'install',
                        help='colcon install base (default: install/ in the checkout)')
    parser.add_argument('--params', type=Path, default=None,
                        help='parameter file of the mooring node (default config/berth.yaml: '
                        "the checkout's, else the installed package's)")
    parser.add_argument('--scenario', type=Path, default=None,
                        help='parameters on top of --params: the free ship and the passing '
                        'ship (default config/berth_demo.yaml, found as --params)')
    parser.add_argument('--out', type=Path, default=None,
                        help='where the run directory demo_<time>/ (bag and plots) is made '
                        '(default: out/ in the checkout, else in the working directory)')
    args = parser.parse_args(argv)

    bad = not_positive(args, ('speed', 'duration'))
    if bad:
        print(f'demo: {bad}', file=sys.stderr)
        return 2
    prefix = args.install.resolve() / PACKAGE
    executables = prefix / 'lib' / PACKAGE
    checkout = (REPO / 'config' / 'berth_demo.yaml').is_file()
    config = REPO / 'config' if checkout else prefix / 'share' / PACKAGE / 'config'
    args.params = args.params or config / 'berth.yaml'
    args.scenario = args.scenario or config / 'berth_demo.yaml'
    args.out = args.out or (REPO / 'out' if checkout else Path('out'))
    missing = [name for name in ('mooring', 'rope_sim')
               if not (executables / name).is_file()]
    if missing:
        print(f'demo: {", ".join(missing)} not found in {executables}: run `make build` first',
              file=sys.stderr)
        return 2
    try:
        setup = demo_setup(args.params, args.scenario)
        plan = read_berthing([args.params, args.scenario], setup)
    except ParameterError as e:
        print(f'demo: {e}', file=sys.stderr)
        return 2
    duration = args.duration or default_duration(setup, plan)
    try:
        run_dir = new_run_directory(args.out)
    except OSError as e:
        print(f'demo: cannot create a run directory in {args.out}: {e.strerror or e}',
              file=sys.stderr)
        return 2
    bag = run_dir / 'bag'

    env = overlay_environment(prefix)
    print(f'demo: ROS_DOMAIN_ID={env["ROS_DOMAIN_ID"]}, {len(setup.lines)} lines from '
          f'{args.params} with {args.scenario}; {duration:g} s simulated at {args.speed:g}x, '
          f'recording to {bag}; Ctrl-C stops early\ndemo: {story(setup, plan)}', flush=True)
    children = {}
    ok = False
    try:
        children['mooring'] = subprocess.Popen(
            [str(executables / 'mooring'), '--ros-args', '--params-file', str(args.params),
             '--params-file', str(args.scenario), '-p', f'record_path:={bag}',
             '-p', 'use_sim_time:=true'],
            env=env, stdin=subprocess.DEVNULL)
        children['berth_demo'] = subprocess.Popen(
            [sys.executable, '-m', f'{PACKAGE}.ros.berth_demo_node', '--params',
             str(args.params), '--params', str(args.scenario), '--speed', str(args.speed),
             '--duration', str(duration)],
            env=env, stdin=subprocess.DEVNULL)
        ok = children['berth_demo'].wait() == 0
    except KeyboardInterrupt:
        print('demo: interrupted', flush=True)
    finally:
        codes = stop(children)
    bad = {name: code for name, code in codes.items() if code != 0}
    if bad:
        print(f'demo: exit codes {bad}', file=sys.stderr)
    print(f'demo: stopped {", ".join(codes)}', flush=True)
    shown = show_bag(executables / 'rope_sim', env, bag, run_dir, story(setup, plan))
    return 0 if ok and not bad and shown else 1


def new_run_directory(base: Path) -> Path:
    """
    Create and return a new directory base/demo_<date>-<time>[_<n>]; never reuse one.

    :param base: where to make it (created if missing).
    :returns: the new, empty directory.
    :raises OSError: base cannot be created or written.
    """
    base.mkdir(parents=True, exist_ok=True)
    stem = 'demo_' + time.strftime('%Y%m%d-%H%M%S')
    for n in range(1, 1000):
        path = base / (stem if n == 1 else f'{stem}_{n}')
        try:
            path.mkdir()
        except FileExistsError:
            continue
        return path.resolve()
    raise FileExistsError(errno.EEXIST, 'too many runs this second', str(base / stem))


def show_bag(rope_sim: Path, env: dict, bag: Path, run_dir: Path, told: str = '') -> bool:
    """
    Describe the recorded bag with `rope_sim info`, draw its plots, say where things are.

    A bag left incomplete (mooring had to be killed) is completed with `rope_sim recover`
    first.

    :param told: the story of the run, for the top of event.png.
    :returns: True if the bag was there, described and plotted.
    """
    if not (bag / 'metadata.yaml').is_file():
        if not bag.is_dir():
            print(f'demo: no bag was recorded at {bag}', file=sys.stderr)
            return False
        print(f'demo: {bag} was not closed; completing it with rope_sim recover', flush=True)
        if subprocess.run([str(rope_sim), 'recover', str(bag)], env=env).returncode != 0:
            return False
    print(f'demo: rope_sim info {bag}', flush=True)
    ok = subprocess.run([str(rope_sim), 'info', str(bag)], env=env).returncode == 0
    from .plot import plot_event
    from ..bag import BagError
    try:
        plots = plot_event(bag, run_dir, told)
    except (BagError, OSError) as e:
        print(f'demo: no plots: {e}', file=sys.stderr)
        return False
    print(f'demo: bag   {bag}', flush=True)
    for plot in plots:
        print(f'demo: plot  {plot}', flush=True)
    return ok


if __name__ == '__main__':
    sys.exit(main())
