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
The nodes' DDS profile: a node that starts beside running publishers sees them at once.

With Fast DDS 2.14 (ROS 2 Jazzy's default middleware), a new participant's first
announcement goes out before it listens, and about half the time it misses the running
participants' one answer: it then waits up to 3 s for their next periodic announcement
before it hears a pose (a plain rclpy subscriber beside a running 50 Hz publisher: first
message 0.25-2.5 s after start, 8 of 20 starts over 1 s; with the profile 0.24-0.65 s, none
of 60). fastdds_discovery.xml, beside this module, says why its one setting cures it.

A user's own profile file always wins: the package's is loaded only when neither
FASTRTPS_DEFAULT_PROFILES_FILE (what Fast DDS 2.x reads) nor FASTDDS_DEFAULT_PROFILES_FILE
(Fast DDS 3.x) is set. Other middlewares do not read either name.
"""

import os
from pathlib import Path
from typing import MutableMapping, Optional

PROFILE = Path(__file__).with_name('fastdds_discovery.xml')
PROFILE_VARIABLES = ('FASTRTPS_DEFAULT_PROFILES_FILE', 'FASTDDS_DEFAULT_PROFILES_FILE')


def use_quick_discovery(environ: MutableMapping[str, str] = os.environ) -> Optional[str]:
    """
    Load the package's profile into the middleware started after this call (rclpy.init).

    :returns: the profile's path, or None when a profile file of the user's is set.
    """
    if any(name in environ for name in PROFILE_VARIABLES):
        return None
    environ[PROFILE_VARIABLES[0]] = str(PROFILE)
    return str(PROFILE)
