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
The .msg texts and RIHS01 hashes of the message types recorded without ROS.

Generated from the installed message packages by
`python -m rope_sim_ros.ros2bag > rope_sim_ros/bag/definitions.py`; a test
fails when they differ from what is installed. Do not edit by hand.
"""

#: canonical type name -> (the share/<pkg>/msg/<Type>.msg text, its RIHS01 hash)
DEFINITIONS = {
    'builtin_interfaces/msg/Duration': (
        '# Duration defines a period between two time points.\n'
        '# Messages of this datatype are of ROS Time following this design:\n'
        '# https://design.ros2.org/articles/clock_and_time.html\n'
        '\n'
        '# The seconds component, valid over all int32 values.\n'
        'int32 sec\n'
        '\n'
        '# The nanoseconds component, valid in the range [0, 1e9), to be added to the seconds co'
        'mponent. \n'
        '# e.g.\n'
        '# The duration -1.7 seconds is represented as {sec: -2, nanosec: 3e8}\n'
        '# The duration 1.7 seconds is represented as {sec: 1, nanosec: 7e8}\n'
        'uint32 nanosec\n',
        'RIHS01_e8d009f659816f758b75334ee1a9ca5b5c0b859843261f14c7f937349599d93b'),
    'builtin_interfaces/msg/Time': (
        '# This message communicates ROS Time defined here:\n'
        '# https://design.ros2.org/articles/clock_and_time.html\n'
        '\n'
        '# The seconds component, valid over all int32 values.\n'
        'int32 sec\n'
        '\n'
        '# The nanoseconds component, valid in the range [0, 1e9), to be added to the seconds co'
        'mponent. \n'
        '# e.g.\n'
        '# The time -1.7 seconds is represented as {sec: -2, nanosec: 3e8}\n'
        '# The time 1.7 seconds is represented as {sec: 1, nanosec: 7e8}\n'
        'uint32 nanosec\n',
        'RIHS01_b106235e25a4c5ed35098aa0a61a3ee9c9b18d197f398b0e4206cea9acf9c197'),
    'diagnostic_msgs/msg/DiagnosticArray': (
        '# This message is used to send diagnostic information about the state of the robot.\n'
        'std_msgs/Header header # for timestamp\n'
        'DiagnosticStatus[] status # an array of components being reported on\n',
        'RIHS01_5a8a36efb05fb25070fa0fb3810290c0e6cd4862b54a8fb975a1ee8dc55a333e'),
    'diagnostic_msgs/msg/DiagnosticStatus': (
        '# This message holds the status of an individual component of the robot.\n'
        '\n'
        '# Possible levels of operations.\n'
        'byte OK=0\n'
        'byte WARN=1\n'
        'byte ERROR=2\n'
        'byte STALE=3\n'
        '\n'
        '# Level of operation enumerated above.\n'
        'byte level\n'
        '# A description of the test/component reporting.\n'
        'string name\n'
        '# A description of the status.\n'
        'string message\n'
        '# A hardware unique string.\n'
        'string hardware_id\n'
        '# An array of values associated with the status.\n'
        'KeyValue[] values\n'
        '\n',
        'RIHS01_b0e3e692ea2d54a8af2f4ef1930e81556a2db55216b771f8a7d2724ed47bf0e4'),
    'diagnostic_msgs/msg/KeyValue': (
        '# What to label this value when viewing.\n'
        'string key\n'
        '# A value to track over time.\n'
        'string value\n',
        'RIHS01_d68081eaa540288c5440753baecef0c4e16e81a5f78ad68902ded5100413bb42'),
    'geometry_msgs/msg/Point': (
        '# This contains the position of a point in free space\n'
        'float64 x\n'
        'float64 y\n'
        'float64 z\n',
        'RIHS01_6963084842a9b04494d6b2941d11444708d892da2f4b09843b9c43f42a7f6881'),
    'geometry_msgs/msg/Pose': (
        '# A representation of pose in free space, composed of position and orientation.\n'
        '\n'
        'Point position\n'
        'Quaternion orientation\n',
        'RIHS01_d501954e9476cea2996984e812054b68026ae0bfae789d9a10b23daf35cc90fa'),
    'geometry_msgs/msg/PoseArray': (
        '# An array of poses with a header for global reference.\n'
        '\n'
        'std_msgs/Header header\n'
        '\n'
        'Pose[] poses\n',
        'RIHS01_af0cc36d190e104d546d168d6b39df04fa4b4ccecf59cb4c9ed328d3d5004aa0'),
    'geometry_msgs/msg/PoseStamped': (
        '# A Pose with reference coordinate frame and timestamp\n'
        '\n'
        'std_msgs/Header header\n'
        'Pose pose\n',
        'RIHS01_10f3786d7d40fd2b54367835614bff85d4ad3b5dab62bf8bca0cc232d73b4cd8'),
    'geometry_msgs/msg/PoseWithCovariance': (
        '# This represents a pose in free space with uncertainty.\n'
        '\n'
        'Pose pose\n'
        '\n'
        '# Row-major representation of the 6x6 covariance matrix\n'
        '# The orientation parameters use a fixed-axis representation.\n'
        '# In order, the parameters are:\n'
        '# (x, y, z, rotation about X axis, rotation about Y axis, rotation about Z axis)\n'
        'float64[36] covariance\n',
        'RIHS01_9a7c0fd234b7f45c6098745ecccd773ca1085670e64107135397aee31c02e1bb'),
    'geometry_msgs/msg/Quaternion': (
        '# This represents an orientation in free space in quaternion form.\n'
        '\n'
        'float64 x 0\n'
        'float64 y 0\n'
        'float64 z 0\n'
        'float64 w 1\n',
        'RIHS01_8a765f66778c8ff7c8ab94afcc590a2ed5325a1d9a076ffff38fbce36f458684'),
    'geometry_msgs/msg/Twist': (
        '# This expresses velocity in free space broken into its linear and angular parts.\n'
        '\n'
        'Vector3  linear\n'
        'Vector3  angular\n',
        'RIHS01_9c45bf16fe0983d80e3cfe750d6835843d265a9a6c46bd2e609fcddde6fb8d2a'),
    'geometry_msgs/msg/TwistWithCovariance': (
        '# This expresses velocity in free space with uncertainty.\n'
        '\n'
        'Twist twist\n'
        '\n'
        '# Row-major representation of the 6x6 covariance matrix\n'
        '# The orientation parameters use a fixed-axis representation.\n'
        '# In order, the parameters are:\n'
        '# (x, y, z, rotation about X axis, rotation about Y axis, rotation about Z axis)\n'
        'float64[36] covariance\n',
        'RIHS01_49f574f033f095d8b6cd1beaca5ca7925e296e84af1716d16c89d38b059c8c18'),
    'geometry_msgs/msg/Vector3': (
        '# This represents a vector in free space.\n'
        '\n'
        '# This is semantically different than a point.\n'
        '# A vector is always anchored at the origin.\n'
        '# When a transform is applied to a vector, only the rotational component is applied.\n'
        '\n'
        'float64 x\n'
        'float64 y\n'
        'float64 z\n',
        'RIHS01_cc12fe83e4c02719f1ce8070bfd14aecd40f75a96696a67a2a1f37f7dbb0765d'),
    'geometry_msgs/msg/Vector3Stamped': (
        '# This represents a Vector3 with reference coordinate frame and timestamp\n'
        '\n'
        '# Note that this follows vector semantics with it always anchored at the origin,\n'
        '# so the rotational elements of a transform are the only parts applied when transformin'
        'g.\n'
        '\n'
        'std_msgs/Header header\n'
        'Vector3 vector\n',
        'RIHS01_d4829622288cbb443886e7ea94ea5671a3b1be6bab4ad04224432a65f7d7887a'),
    'geometry_msgs/msg/Wrench': (
        '# This represents force in free space, separated into its linear and angular parts.\n'
        '\n'
        'Vector3  force\n'
        'Vector3  torque\n',
        'RIHS01_018e8519d57c16adbe97c9fe1460ef21fec7e31bc541de3d653a35895677ce52'),
    'geometry_msgs/msg/WrenchStamped': (
        '# A wrench with reference coordinate frame and timestamp\n'
        '\n'
        'std_msgs/Header header\n'
        'Wrench wrench\n',
        'RIHS01_8dc3deaf06b2ab281f9f9a742a8961c328ca7cec16e3fd6586d3a5c83fa78f77'),
    'nav_msgs/msg/Odometry': (
        '# This represents an estimate of a position and velocity in free space.\n'
        '# The pose in this message should be specified in the coordinate frame given by header.'
        'frame_id\n'
        '# The twist in this message should be specified in the coordinate frame given by the ch'
        'ild_frame_id\n'
        '\n'
        '# Includes the frame id of the pose parent.\n'
        'std_msgs/Header header\n'
        '\n'
        '# Frame id the pose points to. The twist is in this coordinate frame.\n'
        'string child_frame_id\n'
        '\n'
        '# Estimated pose that is typically relative to a fixed world frame.\n'
        'geometry_msgs/PoseWithCovariance pose\n'
        '\n'
        '# Estimated linear and angular velocity relative to child_frame_id.\n'
        'geometry_msgs/TwistWithCovariance twist\n',
        'RIHS01_3cc97dc7fb7502f8714462c526d369e35b603cfc34d946e3f2eda2766dfec6e0'),
    'sensor_msgs/msg/CompressedImage': (
        '# This message contains a compressed image.\n'
        '\n'
        'std_msgs/Header header # Header timestamp should be acquisition time of image\n'
        '                             # Header frame_id should be optical frame of camera\n'
        '                             # origin of frame should be optical center of cameara\n'
        '                             # +x should point to the right in the image\n'
        '                             # +y should point down in the image\n'
        '                             # +z should point into to plane of the image\n'
        '\n'
        'string format                # Specifies the format of the data\n'
        '                             # Acceptable values differ by the image transport used:\n'
        '                             # - compressed_image_transport:\n'
        '                             #     ORIG_PIXFMT; CODEC compressed [COMPRESSED_PIXFMT]\n'
        '                             #   where:\n'
        '                             #   - ORIG_PIXFMT is pixel format of the raw image, i.e.\n'
        '                             #     the content of sensor_msgs/Image/encoding with\n'
        '                             #     values from include/sensor_msgs/image_encodings.h\n'
        '                             #   - CODEC is one of [jpeg, png, tiff]\n'
        '                             #   - COMPRESSED_PIXFMT is only appended for color images'
        '\n'
        '                             #     and is the pixel format used by the compression\n'
        '                             #     algorithm. Valid values for jpeg encoding are:\n'
        '                             #     [bgr8, rgb8]. Valid values for png encoding are:\n'
        '                             #     [bgr8, rgb8, bgr16, rgb16].\n'
        '                             #   If the field is empty or does not correspond to the\n'
        '                             #   above pattern, the image is treated as bgr8 or mono8\n'
        '                             #   jpeg image (depending on the number of channels).\n'
        '                             # - compressed_depth_image_transport:\n'
        '                             #     ORIG_PIXFMT; compressedDepth CODEC\n'
        '                             #   where:\n'
        '                             #   - ORIG_PIXFMT is pixel format of the raw image, i.e.\n'
        '                             #     the content of sensor_msgs/Image/encoding with\n'
        '                             #     values from include/sensor_msgs/image_encodings.h\n'
        '                             #     It is usually one of [16UC1, 32FC1].\n'
        '                             #   - CODEC is one of [png, rvl]\n'
        '                             #   If the field is empty or does not correspond to the\n'
        '                             #   above pattern, the image is treated as png image.\n'
        '                             # - Other image transports can store whatever values they'
        '\n'
        '                             #   need for successful decoding of the image. Refer to\n'
        '                             #   documentation of the other transports for details.\n'
        '\n'
        'uint8[] data                 # Compressed image buffer\n',
        'RIHS01_15640771531571185e2efc8a100baf923961a4d15d5569652e6cb6691e8e371a'),
    'std_msgs/msg/Bool': (
        '# This was originally provided as an example message.\n'
        '# It is deprecated as of Foxy\n'
        '# It is recommended to create your own semantically meaningful message.\n'
        '# However if you would like to continue using this please use the equivalent in example'
        '_msgs.\n'
        '\n'
        'bool data\n',
        'RIHS01_feb91e995ff9ebd09c0cb3d2aed18b11077585839fb5db80193b62d74528f6c9'),
    'std_msgs/msg/ColorRGBA': (
        'float32 r\n'
        'float32 g\n'
        'float32 b\n'
        'float32 a\n',
        'RIHS01_77a7a5b9ae477306097665106e0413ba74440245b1f3d0c6d6405fe5c7813fe8'),
    'std_msgs/msg/Float64': (
        '# This was originally provided as an example message.\n'
        '# It is deprecated as of Foxy\n'
        '# It is recommended to create your own semantically meaningful message.\n'
        '# However if you would like to continue using this please use the equivalent in example'
        '_msgs.\n'
        '\n'
        'float64 data\n',
        'RIHS01_705ba9c3d1a09df43737eb67095534de36fd426c0587779bda2bc51fe790182a'),
    'std_msgs/msg/Float64MultiArray': (
        '# This was originally provided as an example message.\n'
        '# It is deprecated as of Foxy\n'
        '# It is recommended to create your own semantically meaningful message.\n'
        '# However if you would like to continue using this please use the equivalent in example'
        '_msgs.\n'
        '\n'
        '# Please look at the MultiArrayLayout message definition for\n'
        '# documentation on all multiarrays.\n'
        '\n'
        'MultiArrayLayout  layout        # specification of data layout\n'
        'float64[]         data          # array of data\n',
        'RIHS01_1025ddc6b9552d191f89ef1a8d2f60f3d373e28b283d8891ddcc974e8c55397f'),
    'std_msgs/msg/Header': (
        '# Standard metadata for higher-level stamped data types.\n'
        '# This is generally used to communicate timestamped data\n'
        '# in a particular coordinate frame.\n'
        '\n'
        '# Two-integer timestamp that is expressed as seconds and nanoseconds.\n'
        'builtin_interfaces/Time stamp\n'
        '\n'
        '# Transform frame with which this data is associated.\n'
        'string frame_id\n',
        'RIHS01_f49fb3ae2cf070f793645ff749683ac6b06203e41c891e17701b1cb597ce6a01'),
    'std_msgs/msg/MultiArrayDimension': (
        '# This was originally provided as an example message.\n'
        '# It is deprecated as of Foxy\n'
        '# It is recommended to create your own semantically meaningful message.\n'
        '# However if you would like to continue using this please use the equivalent in example'
        '_msgs.\n'
        '\n'
        'string label   # label of given dimension\n'
        'uint32 size    # size of given dimension (in type units)\n'
        'uint32 stride  # stride of given dimension\n',
        'RIHS01_5e773a60a4c7fc8a54985f307c7837aa2994252a126c301957a24e31282c9cbe'),
    'std_msgs/msg/MultiArrayLayout': (
        '# This was originally provided as an example message.\n'
        '# It is deprecated as of Foxy\n'
        '# It is recommended to create your own semantically meaningful message.\n'
        '# However if you would like to continue using this please use the equivalent in example'
        '_msgs.\n'
        '\n'
        '# The multiarray declares a generic multi-dimensional array of a\n'
        '# particular data type.  Dimensions are ordered from outer most\n'
        '# to inner most.\n'
        '#\n'
        '# Accessors should ALWAYS be written in terms of dimension stride\n'
        '# and specified outer-most dimension first.\n'
        '#\n'
        '# multiarray(i,j,k) = data[data_offset + dim_stride[1]*i + dim_stride[2]*j + k]\n'
        '#\n'
        '# A standard, 3-channel 640x480 image with interleaved color channels\n'
        '# would be specified as:\n'
        '#\n'
        '# dim[0].label  = "height"\n'
        '# dim[0].size   = 480\n'
        '# dim[0].stride = 3*640*480 = 921600  (note dim[0] stride is just size of image)\n'
        '# dim[1].label  = "width"\n'
        '# dim[1].size   = 640\n'
        '# dim[1].stride = 3*640 = 1920\n'
        '# dim[2].label  = "channel"\n'
        '# dim[2].size   = 3\n'
        '# dim[2].stride = 3\n'
        '#\n'
        '# multiarray(i,j,k) refers to the ith row, jth column, and kth channel.\n'
        '\n'
        'MultiArrayDimension[] dim # Array of dimension properties\n'
        'uint32 data_offset        # padding bytes at front of data\n',
        'RIHS01_4c66e6f78e740ac103a94cf63259f968e48c617e7699e829b63c21a5cb50dac6'),
    'std_msgs/msg/String': (
        '# This was originally provided as an example message.\n'
        '# It is deprecated as of Foxy\n'
        '# It is recommended to create your own semantically meaningful message.\n'
        '# However if you would like to continue using this please use the equivalent in example'
        '_msgs.\n'
        '\n'
        'string data\n',
        'RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18'),
    'visualization_msgs/msg/Marker': (
        '# See:\n'
        '#  - http://www.ros.org/wiki/rviz/DisplayTypes/Marker\n'
        '#  - http://www.ros.org/wiki/rviz/Tutorials/Markers%3A%20Basic%20Shapes\n'
        '#\n'
        '# for more information on using this message with rviz.\n'
        '\n'
        'int32 ARROW=0\n'
        'int32 CUBE=1\n'
        'int32 SPHERE=2\n'
        'int32 CYLINDER=3\n'
        'int32 LINE_STRIP=4\n'
        'int32 LINE_LIST=5\n'
        'int32 CUBE_LIST=6\n'
        'int32 SPHERE_LIST=7\n'
        'int32 POINTS=8\n'
        'int32 TEXT_VIEW_FACING=9\n'
        'int32 MESH_RESOURCE=10\n'
        'int32 TRIANGLE_LIST=11\n'
        'int32 ARROW_STRIP=12\n'
        '\n'
        'int32 ADD=0\n'
        'int32 MODIFY=0\n'
        'int32 DELETE=2\n'
        'int32 DELETEALL=3\n'
        '\n'
        '# Header for timestamp and frame id.\n'
        'std_msgs/Header header\n'
        '# Namespace in which to place the object.\n'
        '# Used in conjunction with id to create a unique name for the object.\n'
        'string ns\n'
        '# Object ID used in conjunction with the namespace for manipulating and deleting the ob'
        'ject later.\n'
        'int32 id\n'
        '# Type of object.\n'
        'int32 type\n'
        '# Action to take; one of:\n'
        '#  - 0 add/modify an object\n'
        '#  - 1 (deprecated)\n'
        '#  - 2 deletes an object (with the given ns and id)\n'
        '#  - 3 deletes all objects (or those with the given ns if any)\n'
        'int32 action\n'
        '# Pose of the object with respect the frame_id specified in the header.\n'
        'geometry_msgs/Pose pose\n'
        '# Scale of the object; 1,1,1 means default (usually 1 meter square).\n'
        'geometry_msgs/Vector3 scale\n'
        '# Color of the object; in the range: [0.0-1.0]\n'
        'std_msgs/ColorRGBA color\n'
        '# How long the object should last before being automatically deleted.\n'
        '# 0 indicates forever.\n'
        'builtin_interfaces/Duration lifetime\n'
        '# If this marker should be frame-locked, i.e. retransformed into its frame every timest'
        'ep.\n'
        'bool frame_locked\n'
        '\n'
        '# Only used if the type specified has some use for them (eg. POINTS, LINE_STRIP, ARROW_'
        'STRIP, etc.)\n'
        'geometry_msgs/Point[] points\n'
        '# Only used if the type specified has some use for them (eg. POINTS, LINE_STRIP, etc.)'
        '\n'
        '# The number of colors provided must either be 0 or equal to the number of points provi'
        'ded.\n'
        '# NOTE: alpha is not yet used\n'
        'std_msgs/ColorRGBA[] colors\n'
        '\n'
        '# Texture resource is a special URI that can either reference a texture file in\n'
        '# a format acceptable to (resource retriever)[https://docs.ros.org/en/rolling/p/resourc'
        'e_retriever/]\n'
        '# or an embedded texture via a string matching the format:\n'
        '#   "embedded://texture_name"\n'
        'string texture_resource\n'
        '# An image to be loaded into the rendering engine as the texture for this marker.\n'
        '# This will be used iff texture_resource is set to embedded.\n'
        'sensor_msgs/CompressedImage texture\n'
        '# Location of each vertex within the texture; in the range: [0.0-1.0]\n'
        'UVCoordinate[] uv_coordinates\n'
        '\n'
        '# Only used for text markers\n'
        'string text\n'
        '\n'
        '# Only used for MESH_RESOURCE markers.\n'
        '# Similar to texture_resource, mesh_resource uses resource retriever to load a mesh.\n'
        '# Optionally, a mesh file can be sent in-message via the mesh_file field. If doing so,'
        '\n'
        '# use the following format for mesh_resource:\n'
        '#   "embedded://mesh_name"\n'
        'string mesh_resource\n'
        'MeshFile mesh_file\n'
        'bool mesh_use_embedded_materials\n',
        'RIHS01_45b13ccf791f225962bf74e746f9644518855d783a6f42ba0cc14fde2b4f3ce0'),
    'visualization_msgs/msg/MarkerArray': (
        'Marker[] markers\n',
        'RIHS01_86cb8800b6fb05b5eff1abd7a56f62a5641d3ae9a1c29e78e67e704f1d067dcf'),
    'visualization_msgs/msg/MeshFile': (
        '# Used to send raw mesh files.\n'
        '\n'
        '# The filename is used for both debug purposes and to provide a file extension\n'
        '# for whatever parser is used.\n'
        'string filename\n'
        '\n'
        '# This stores the raw text of the mesh file.\n'
        'uint8[] data\n',
        'RIHS01_7710ece15a148fb7c9b546364cfb215bb06098087bd6394fe5b73a493508f8c4'),
    'visualization_msgs/msg/UVCoordinate': (
        '# Location of the pixel as a ratio of the width of a 2D texture.\n'
        '# Values should be in range: [0.0-1.0].\n'
        'float32 u\n'
        'float32 v\n',
        'RIHS01_f27f7ed21fe360c6066944f856b801a0c0d1e94e815b6886444b42d90b196a26'),
}
