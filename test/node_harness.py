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

"""The installed mooring_line executable as a child process, shared by the node tests."""

import contextlib
import gc
from pathlib import Path
import signal
import subprocess
import time
from typing import List

# Every node started in this test session, for the failure report (conftest.py).
STARTED: List['NodeProcess'] = []


@contextlib.contextmanager
def no_gc_pauses():
    """
    Keep the cyclic garbage collector out of a timed publishing loop.

    A full collection in a pytest process holding the messages of earlier tests took up to
    0.13 s: long enough to look like a pose stream falling silent.
    """
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


class NodeProcess:
    """mooring_line from a colcon install with the package's parameter file, its log in a file."""

    def __init__(self, install: Path, env: dict, log: Path, namespace: str, *ros_args: str):
        """Start the node in namespace with extra --ros-args (e.g. '-p', 'length:=40')."""
        self.log = log
        self.namespace = namespace
        self.started = time.monotonic()
        command = [
            str(install / 'lib' / 'rope_sim_ros' / 'mooring_line'), '--ros-args',
            '--params-file', str(install / 'share' / 'rope_sim_ros' / 'config' /
                                 'mooring_line.yaml'),
            '-r', f'__ns:={namespace}', *ros_args]
        with open(log, 'w') as f:
            self.process = subprocess.Popen(
                command, env=env, stdin=subprocess.DEVNULL, stdout=f, stderr=subprocess.STDOUT)
        STARTED.append(self)

    def text(self) -> str:
        """Return the node's output so far."""
        return self.log.read_text(errors='replace')

    def stop(self, signum: int = signal.SIGINT, timeout: float = 20.0) -> int:
        """Send a signal (Ctrl-C by default), wait for the exit and return the exit code."""
        if self.process.poll() is None:
            self.process.send_signal(signum)
        try:
            return self.process.wait(timeout)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
            raise AssertionError(f'node ignored signal {signum} for {timeout} s:\n{self.text()}')

    def interrupt(self, timeout: float = 15.0) -> int:
        """Send SIGINT (Ctrl-C) and return the exit code."""
        return self.stop(signal.SIGINT, timeout)
