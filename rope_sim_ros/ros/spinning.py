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

import contextlib
import signal
import time
from typing import List

import rclpy
from rclpy.executors import Executor, ExternalShutdownException, SingleThreadedExecutor
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.signals import (get_current_signal_handlers_options, install_signal_handlers,
                           SignalHandlerOptions, uninstall_signal_handlers)
from rclpy.timer import Timer

# How long a failed spin waits for a signal's shutdown to land before it re-raises [s].
SHUTDOWN_GRACE = 1.0
# The longest one wait of the executor lasts: how soon a signal ends the spin [s].
SPIN_TIMEOUT = 0.1
STOPPING_SIGNALS = (signal.SIGINT, signal.SIGTERM)


def spin_until_shutdown(node: Node) -> None:
    """
    Spin node until Ctrl-C or SIGTERM, or until its context shuts down.

    The executor is executor_for(node).

    While it spins, SIGINT and SIGTERM only ask the loop to stop (within SPIN_TIMEOUT). A
    handler that raises, as Ctrl-C's KeyboardInterrupt does, raises inside whichever
    callback is running, and the executor reports that as a fatal error with its traceback;
    rclpy's own handlers would shut the context down under a running callback. An error out
    of the spin after a signal is taken for the signal's doing: a Ctrl-C landing inside a
    message conversion comes out of pybind11 as a RuntimeError ('Unable to convert call
    argument'). Without a signal, a failure is re-raised unless the context is shut down
    within SHUTDOWN_GRACE seconds (by another thread's signal handling).
    """
    stop: List[int] = []
    executor = executor_for(node)
    executor.add_node(node)
    try:
        with _signals_stop(stop):
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


@contextlib.contextmanager
def _signals_stop(stop: List[int]):
    """
    Inside the block, SIGINT and SIGTERM append their number to `stop` and do nothing else.

    Afterwards the handlers are as before, rclpy's included.
    """
    rclpy_options = get_current_signal_handlers_options()
    taken = False
    try:
        with _stopping_signals(lambda signum, frame: stop.append(signum)) as taken:
            yield
    finally:
        if taken and rclpy_options != SignalHandlerOptions.NO:
            # rclpy's handlers go back on top, chaining to the ones just restored
            uninstall_signal_handlers()
            install_signal_handlers(rclpy_options)


def signals_ignored():
    """Ignore SIGINT and SIGTERM inside the block (main thread only); SIGKILL still works."""
    return _stopping_signals(signal.SIG_IGN)


@contextlib.contextmanager
def _stopping_signals(handler):
    """
    Give SIGINT and SIGTERM to `handler` inside the block; yield whether they were taken.

    Outside the main thread signals are left alone (False). Afterwards the Python handlers
    are as before.
    """
    saved = {}
    try:
        for number in STOPPING_SIGNALS:
            saved[number] = signal.signal(number, handler)
    except ValueError:  # not the main thread
        pass
    try:
        yield bool(saved)
    finally:
        for number, previous in saved.items():
            signal.signal(number, previous if previous is not None else signal.SIG_DFL)


def set_timer_period(timer: Timer, period: float) -> None:
    """
    Give a timer a new period [s], counted from now.

    The events executor keeps each timer in a queue by its next call time, which a new
    period alone does not move (a 20 ms tick changed to 1 ms still waited out its 20 ms):
    the reset moves it.
    """
    timer.timer_period_ns = round(period * 1e9)
    timer.reset()
