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
The one progress bar of the offline commands: a run's outputs, a study's cases.

One line on a TTY (stderr by default), rewritten in place: the bar, how far the work is, the
time since it started and the time left at the pace so far.
"""

import math
import sys
import time
from typing import Optional


class Progress:
    """
    A text progress bar on a stream, drawn only when the stream is a TTY (or enabled).

    Called as simulate's progress (outputs done of total at simulated time t); show() draws
    any other count (study/cluster.py StudyProgress: cases). A drawing rewrites the line
    (carriage return) once ``delay`` seconds have passed, at most once every ``interval``
    seconds but for the last; finish() ends the line with a newline if anything was drawn.
    """

    def __init__(self, stream=None, delay: float = 2.0, width: int = 30,
                 enabled: Optional[bool] = None, interval: float = 0.1) -> None:
        """
        Prepare the bar.

        :param stream: where to draw (default sys.stderr).
        :param delay: seconds before the first drawing (a quick run shows none).
        :param width: characters of the bar.
        :param enabled: force on/off; None = only when the stream is a TTY.
        :param interval: the least seconds between two drawings (the last one aside).
        """
        self.stream = stream if stream is not None else sys.stderr
        if enabled is None:
            isatty = getattr(self.stream, 'isatty', None)
            enabled = bool(isatty and isatty())
        self.enabled = enabled
        self.delay = delay
        self.width = width
        self.interval = interval
        self._start = time.monotonic()
        self._last = -math.inf
        self._drawn = False

    def __call__(self, done: int, total: int, t: float) -> None:
        """Report done of total outputs, at simulated time t."""
        fraction = done / total if total else 1.0
        self.show(done, total, f'{100.0 * fraction:5.1f} % t = {t:.2f} s')

    def show(self, done: int, total: int, what: str) -> None:
        """Draw done of total, `what` saying how far (unless too early or too soon again)."""
        if not self.enabled:
            return
        now = time.monotonic()
        if now - self._start < self.delay or (now - self._last < self.interval
                                              and done < total):
            return
        self._last = now
        self.stream.write('\r' + self.line(done, total, what) + '\x1b[K')
        self.stream.flush()
        self._drawn = True

    def line(self, done: int, total: int, what: str) -> str:
        """Return the bar's line: the bar, `what`, the time so far and the time left."""
        fraction = done / total if total else 1.0
        filled = int(round(self.width * fraction))
        elapsed = time.monotonic() - self._start
        left = elapsed * (1.0 - fraction) / fraction if fraction > 0.0 else math.inf
        eta = f', ~{_clock(left)} left' if math.isfinite(left) and done < total else ''
        return f'[{"#" * filled}{"." * (self.width - filled)}] {what}, {_clock(elapsed)}{eta}'

    def clear(self) -> None:
        """Clear the bar's line, for a line of text; the next drawing draws it again."""
        if self._drawn:
            self.stream.write('\r\x1b[K')
            self.stream.flush()
            self._drawn = False
            self._last = -math.inf

    def finish(self) -> None:
        """End the line if the bar was drawn."""
        if self._drawn:
            self.stream.write('\n')
            self.stream.flush()
            self._drawn = False


def _clock(seconds: float) -> str:
    seconds = int(round(seconds))
    return f'{seconds // 3600}:{seconds // 60 % 60:02d}:{seconds % 60:02d}' if seconds >= 3600 \
        else f'{seconds // 60}:{seconds % 60:02d}'
