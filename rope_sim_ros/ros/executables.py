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
The entry points of the executables: Ctrl-C at any moment of start-up ends quietly.

The launchers in bin/ (what colcon installs, what ros2 run runs) take SIGINT over in their
first statements and call these. Each imports its module before it calls main(): for the
nodes rclpy, numpy and numba, up to 0.7 s in which Ctrl-C raised KeyboardInterrupt out of
an import and printed a traceback (6 of 6 tries in the first 0.5 s). These entry points
import only the standard library; each imports its module and runs its main() inside a
try, so that a Ctrl-C that main() does not handle itself exits with 130 (128 + SIGINT, what
a shell reports for Ctrl-C) and no traceback. main() handles the later ones as before (exit 0).

A Ctrl-C can also surface as another error: rclpy's signal handler shuts its context down
first, so a node being created or rclpy.try_shutdown() racing it raised RCLError ('the
given context is not valid', 'rcl_shutdown already called'; 3 of 40 Ctrl-C in the first
0.2 s of bag_replay). After a Ctrl-C such an error is taken for the Ctrl-C too.

Once main() is over, Ctrl-C is ignored: Python restores the default action of SIGINT while
it finalizes, and a Ctrl-C then killed the process by the signal (bag_replay with a
missing bag, 16 of 40 Ctrl-C between 0.21 and 0.32 s, after its error line).

A KeyboardInterrupt raised in a destructor interrupts nothing: Python prints 'Exception
ignored in: <function RcutilsLogger.__del__ ...>' with a traceback and goes on (1 in about
60 Ctrl-C of bag_replay as it exited; a mooring_line interrupted while starting under load
ran on). Here it is kept quiet, and the signal is sent again REDELIVERY s later, out of the
destructor, unless main() is over. The same Ctrl-C can cut a constructor short, between
two of its assignments: the half-built object's destructor then reads an attribute that was
never set (rclpy's Future.__del__: "'Task' object has no attribute '_exception'", printed
with a traceback as a node was interrupted, 1 in about 600 runs of the node tests). After a
Ctrl-C such an AttributeError in a destructor is kept quiet too.

Some import swallows a KeyboardInterrupt with a bare except (a mooring_line interrupted 0.075 s
into its start ran on, deaf, 1 in about 30 tries under load): a Ctrl-C seen while importing
ends the start with 130 before main() runs, whether or not its exception got through.

Before this module runs, the launcher's handler ends a Ctrl-C with 130; see bin/mooring_line.
"""

import importlib
import os
import signal
import sys
import threading

EXIT_INTERRUPTED = 130  # 128 + SIGINT
REDELIVERY = 0.05  # [s] destructors take microseconds


class _Interrupted:
    """A SIGINT handler that raises KeyboardInterrupt (as Python's own) and remembers it."""

    def __init__(self):
        self.seen = False
        self.done = False  # main() is over: nothing left to interrupt
        self.redelivery = None  # the timer sending a SIGINT lost in a destructor again

    def __call__(self, signum, frame):
        self.seen = True
        if not self.done:
            raise KeyboardInterrupt

    def unraisable(self, unraisable) -> None:
        """
        Send a KeyboardInterrupt raised in a destructor again; report anything else.

        Except an AttributeError after a Ctrl-C: the destructor of an object whose
        constructor the Ctrl-C interrupted (see the module's docstring).
        """
        if issubclass(unraisable.exc_type, AttributeError) and self.seen:
            return
        if not issubclass(unraisable.exc_type, KeyboardInterrupt):
            sys.__unraisablehook__(unraisable)
        elif not self.done:
            self.redelivery = threading.Timer(REDELIVERY, os.kill,
                                              (os.getpid(), signal.SIGINT))
            self.redelivery.daemon = True  # never holds the exit up
            self.redelivery.start()


def _run(module: str, function: str = 'main') -> int:
    """Import rope_sim_ros.<module> and return its function(); 130 after Ctrl-C."""
    interrupted = _Interrupted()
    try:
        # inside the try: a Ctrl-C that lands as signal.signal returns raises here already
        # (seen in CI at 0.02 s). rclpy.init() keeps the handler: rclpy's own calls it after
        # shutting rclpy down.
        signal.signal(signal.SIGINT, interrupted)
        sys.unraisablehook = interrupted.unraisable
        entry = importlib.import_module(f'rope_sim_ros.{module}')
        if interrupted.seen:  # a Ctrl-C whose KeyboardInterrupt an import swallowed
            return EXIT_INTERRUPTED
        return getattr(entry, function)()
    except KeyboardInterrupt:
        return EXIT_INTERRUPTED
    except Exception:
        if interrupted.seen:
            return EXIT_INTERRUPTED
        raise
    finally:
        interrupted.done = True  # no call before it, so no signal handler runs in between
        signal.signal(signal.SIGINT, signal.SIG_IGN)


def mooring_line() -> int:
    """Run the mooring_line node (rope_sim_ros.ros.node.main_line)."""
    return _run('ros.node', 'main_line')


def mooring() -> int:
    """Run the mooring node (rope_sim_ros.ros.node.main_mooring)."""
    return _run('ros.node', 'main_mooring')


def ship_motion() -> int:
    """Run the ship_motion node (rope_sim_ros.ros.ship_motion_node.main)."""
    return _run('ros.ship_motion_node')


def line_monitor() -> int:
    """Run the line_monitor node (rope_sim_ros.ros.line_monitor_node.main)."""
    return _run('ros.line_monitor_node')


def bag_replay() -> int:
    """Play a bag (rope_sim_ros.ros.bag_replay_node.main)."""
    return _run('ros.bag_replay_node')


def rope_sim() -> int:
    """Run the rope_sim command line (rope_sim_ros.offline.cli.main)."""
    return _run('offline.cli')


# Each executable's entry point: its launcher (bin/launcher, installed under its name)
# runs the one its file is named for.
ENTRY_POINTS = {'mooring_line': mooring_line, 'mooring': mooring, 'ship_motion': ship_motion,
                'line_monitor': line_monitor, 'bag_replay': bag_replay, 'rope_sim': rope_sim}


def run_named(path: str) -> int:
    """Run the executable a launcher file is named for (its file name: mooring_line, ...)."""
    name = path.rsplit('/', 1)[-1]
    entry = ENTRY_POINTS.get(name)
    if entry is None:
        print(f'{path}: not an executable of rope_sim_ros (known: '
              f'{", ".join(ENTRY_POINTS)})', file=sys.stderr)
        return 2
    return entry()
