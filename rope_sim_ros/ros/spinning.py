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

"""Spin a node until Ctrl-C or SIGTERM, both ending quietly (the nodes' shared main loop)."""

import time

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node

# How long a failed spin waits for a signal's shutdown to land before it re-raises [s].
SHUTDOWN_GRACE = 1.0


def spin_until_shutdown(node: Node) -> None:
    """
    Spin node until Ctrl-C (KeyboardInterrupt) or SIGTERM.

    A signal can end a spin with another exception, a moment before rclpy's signal handling
    shuts the context down: a Ctrl-C landing inside a message conversion comes out of
    pybind11 as a RuntimeError ('Unable to convert call argument'), and a SIGTERM between
    two waits as 'the given context is not valid'. So a failure is re-raised only if the
    context is still valid SHUTDOWN_GRACE seconds later.
    """
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except Exception:
        deadline = time.monotonic() + SHUTDOWN_GRACE
        while rclpy.ok() and time.monotonic() < deadline:
            time.sleep(0.01)
        if rclpy.ok():
            raise
