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

"""Spin a node until Ctrl-C or SIGTERM, both ending quietly: the nodes' main loop and signals."""

import gc
import signal
import time
from typing import Callable, List, Tuple, Type

import rclpy
from rclpy.executors import Executor, ExternalShutdownException, SingleThreadedExecutor
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.timer import Timer

from .discovery import use_quick_discovery

# How long a failed spin waits for a signal's shutdown to land before it re-raises [s].
SHUTDOWN_GRACE = 1.0
# The longest one wait of the executor lasts: how soon a signal ends the spin [s].
SPIN_TIMEOUT = 0.1
STOPPING_SIGNALS = (signal.SIGINT, signal.SIGTERM)


def spin_until_shutdown(node: Node) -> None:
    """
    Spin node until Ctrl-C or SIGTERM, or until its context shuts down.

    The executor is executor_for(node). For an executable's main thread: from the first
    statement to the end of the process, SIGINT and SIGTERM only ask the loop to stop
    (within SPIN_TIMEOUT), however often they come. A terminal's Ctrl-C reaches a node
    started by `ros2 launch` twice (the terminal's SIGINT to the process group, then
    launch's own): with the raising handlers back after the first, the second raised
    KeyboardInterrupt inside a C++ call of the executor being torn down, and the node died
    with 'terminate called after throwing an instance of pybind11::error_already_set' (2 of
    7 Ctrl-C of a launch), before its bag was closed. rclpy's own handlers would shut the
    context down under a running callback.

    A handler that raises, as Ctrl-C's KeyboardInterrupt does, raises inside whichever
    callback is running, and the executor reports that as a fatal error with its traceback.
    An error out of the spin after a signal is taken for the signal's doing: a Ctrl-C landing
    inside a message conversion comes out of pybind11 as a RuntimeError ('Unable to convert
    call argument'). Without a signal, a failure is re-raised unless the context is shut
    down within SHUTDOWN_GRACE seconds (by another thread's signal handling).
    """
    stop = take_stopping_signals()
    executor = executor_for(node)
    executor.add_node(node)
    try:
        while not stop and node.context.ok():
            executor.spin_once(timeout_sec=SPIN_TIMEOUT)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except Exception:
        if stop:
            return
        deadline = time.monotonic() + SHUTDOWN_GRACE
        while rclpy.ok() and time.monotonic() < deadline:
            time.sleep(0.01)
        if rclpy.ok():
            raise
    finally:
        executor.remove_node(node)


def run_node(start: Callable[[], Node], name: str, errors: Tuple[Type[Exception], ...],
             args=None) -> int:
    """
    Start a node, spin it until Ctrl-C or SIGTERM, tear it down: an executable's main.

    Ctrl-C or SIGTERM during the start ends it cleanly too (exit code 0).

    :param start: makes the node (after rclpy.init).
    :param name: the logger's name for a start-up error.
    :param errors: what start raises for a user's mistake: logged as one line, exit code 2.
    """
    use_quick_discovery()
    rclpy.init(args=args)
    try:
        node = start()
    except errors as e:
        rclpy.logging.get_logger(name).error(str(e))
        rclpy.try_shutdown()
        return 2
    except KeyboardInterrupt:
        rclpy.try_shutdown()
        return 0
    except Exception:
        if rclpy.ok():
            raise
        return 0  # SIGTERM during start-up: rclpy shut the context down under us
    # What start-up allocated (rclpy, numpy, numba: ~1e5 objects) lives as long as the node:
    # keep it out of the cyclic collector, whose full passes over it took ~45 ms mid-run.
    gc.freeze()
    try:
        # from here to the end, SIGINT and SIGTERM only stop the spin: the node's teardown
        # and its bag's closing run whatever signals come (a terminal's and ros2 launch's)
        spin_until_shutdown(node)
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


def take_stopping_signals() -> List[int]:
    """
    From now on, SIGINT and SIGTERM only append their number to the returned list.

    For the rest of the process (the main thread's handlers; elsewhere nothing changes and
    the list stays empty): they stop the spin and never interrupt what comes after it, the
    node's teardown and the closing of its bag.
    """
    try:
        for number in STOPPING_SIGNALS:
            signal.signal(number, _STOPS.record)
    except ValueError:  # not the main thread
        pass
    return _STOPS.seen


class _Stops:
    """A signal handler that keeps the signals' numbers and does nothing else."""

    def __init__(self):
        self.seen: List[int] = []

    def record(self, signum, frame) -> None:
        self.seen.append(signum)


_STOPS = _Stops()


def executor_for(node: Node) -> Executor:
    """
    Return the executor to spin node on: the events executor, or under use_sim_time rclpy's.

    The events executor's loop is C++. rclpy's Python executor walks all of a node's
    subscriptions, timers and services at every wake-up: a node shaped like the 16-line
    mooring node, taking 100 Hz poses and publishing a wrench back, cost 12-14 % of a core
    in that walk alone, 4 % on the events executor. But the events executor (experimental
    in rclpy 7.1; its timers were written for the system clock, ros2/rclcpp issue 2457)
    did not follow a simulated clock on a busy machine: under a /clock that crept on a tick
    at a time, the mooring node took neither a tick nor a /clock message for 30 s at a
    stretch, its ropes fell behind the clock and skipped ahead, 2-4 times in 40 simulated
    seconds; on rclpy's own executor, under the same load, never. So under use_sim_time a
    node spins on rclpy's. The choice is made once, at the start, from use_sim_time then.
    """
    if node.get_parameter('use_sim_time').value:
        return SingleThreadedExecutor(context=node.context)
    return EventsExecutor(context=node.context)


def set_timer_period(timer: Timer, period: float) -> None:
    """
    Give a timer a new period [s], counted from now.

    The events executor keeps each timer in a queue by its next call time, which a new
    period alone does not move (a 20 ms tick changed to 1 ms still waited out its 20 ms):
    the reset moves it.
    """
    timer.timer_period_ns = round(period * 1e9)
    timer.reset()
