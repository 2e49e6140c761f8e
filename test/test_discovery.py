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
The nodes' DDS profile: loaded by the installed package, read by Fast DDS, a user's own first.

A node started beside running publishers waited up to 3 s to hear them (Fast DDS 2.14 misses
the running participants' answer to its first announcement about half the time); the profile
the nodes load cures it. How soon a node hears a publisher is a benchmark's question
(benchmarks/cold_start.py); here: that the profile is where the nodes look, that Fast DDS
reads it without complaint under the name set, and that a user's profile file is left alone.
"""

from pathlib import Path
import subprocess
import sys
import xml.etree.ElementTree as ElementTree

from rope_sim_ros.ros import discovery

# A process that does what the nodes do before rclpy.init (the discovery module of whichever
# rope_sim_ros its PYTHONPATH finds, its profile swapped for argv[1] if given), then makes a
# node: Fast DDS parses the profile file as the participant is made.
START = """
import sys
from pathlib import Path
import rclpy
from rope_sim_ros.ros import discovery
if len(sys.argv) > 1:
    discovery.PROFILE = Path(sys.argv[1])
print(discovery.use_quick_discovery())
rclpy.init()
rclpy.create_node('discovery_check').destroy_node()
rclpy.shutdown()
"""


def start(env: dict, *args: str, user_file=None) -> subprocess.CompletedProcess:
    """Run START (out of the source tree) with no profile file or the user's; its output."""
    env = {k: v for k, v in env.items() if k not in discovery.PROFILE_VARIABLES}
    if user_file:
        env['FASTRTPS_DEFAULT_PROFILES_FILE'] = str(user_file)
    return subprocess.run([sys.executable, '-c', START, *args], env=env, capture_output=True,
                          text=True, timeout=60, cwd=Path(__file__).parent)


def test_the_profile_sets_only_the_discovery_writers_flow():
    root = ElementTree.parse(discovery.PROFILE).getroot()
    namespace = {'p': 'http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles'}
    participants = root.findall('p:participant', namespace)
    assert [p.get('is_default_profile') for p in participants] == ['true']
    rtps = participants[0].find('p:rtps', namespace)
    assert [child.tag.split('}')[1] for child in rtps] == ['throughputController']
    limit = rtps.find('p:throughputController', namespace)
    # 100 MB a millisecond: a flow that never holds a discovery message back
    assert int(limit.find('p:bytesPerPeriod', namespace).text) >= 1e8
    assert int(limit.find('p:periodMillisecs', namespace).text) == 1


def test_a_users_profile_file_is_left_as_it_is():
    for name in ('FASTRTPS_DEFAULT_PROFILES_FILE', 'FASTDDS_DEFAULT_PROFILES_FILE'):
        environ = {name: '/home/user/my_profiles.xml'}
        assert discovery.use_quick_discovery(environ) is None
        assert environ == {name: '/home/user/my_profiles.xml'}
    environ = {'ROS_DOMAIN_ID': '7'}
    assert discovery.use_quick_discovery(environ) == str(discovery.PROFILE)
    assert environ == {'ROS_DOMAIN_ID': '7',
                       'FASTRTPS_DEFAULT_PROFILES_FILE': str(discovery.PROFILE)}


def test_the_installed_package_loads_its_profile_and_fast_dds_reads_it(
        colcon_install, colcon_env, tmp_path):
    site_packages = colcon_install / 'lib' / 'python{}.{}'.format(
        *sys.version_info[:2]) / 'site-packages'
    installed = site_packages / 'rope_sim_ros' / 'ros' / 'fastdds_discovery.xml'
    assert installed.read_text() == discovery.PROFILE.read_text()
    # The installed module points Fast DDS at the installed file, which parses cleanly.
    done = start(colcon_env)
    assert done.returncode == 0, done.stderr
    assert Path(done.stdout.split()[0]).resolve() == installed.resolve()
    assert 'XMLPARSER' not in done.stdout + done.stderr
    # Fast DDS reads the variable set (and would say so of a profile it cannot take): the
    # same profile with its one element misspelt.
    wrong = tmp_path / 'wrong.xml'
    wrong.write_text(installed.read_text().replace('throughputController', 'throughputControler'))
    done = start(colcon_env, str(wrong))
    assert done.returncode == 0, done.stderr
    said = done.stdout + done.stderr  # (Fast DDS logs to stdout)
    assert 'Name: throughputControler' in said and str(wrong) in said, said
    # A user's file instead: the module leaves it; Fast DDS reads the user's.
    done = start(colcon_env, user_file=wrong)
    said = done.stdout + done.stderr
    assert said.split()[0] == 'None' and 'Name: throughputControler' in said, said
