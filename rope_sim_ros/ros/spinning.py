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

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node


def spin_until_shutdown(node: Node) -> None:
    """
    Spin node until Ctrl-C (KeyboardInterrupt) or SIGTERM.

    rclpy's SIGTERM handler shuts the context down; if that lands between two waits, the next
    wait fails with 'the given context is not valid' (an RCLError) rather than
    ExternalShutdownException. A failure while the context is still valid is re-raised.
    """
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except Exception:
        if rclpy.ok():
            raise
