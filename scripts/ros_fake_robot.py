#!/usr/bin/python3
"""A stand-in for a robot's base driver, robot_state_publisher and depth camera driver, for
scripts/ros_rviz_screenshot.sh. Replays a synthetic sequence (`slambooster synth --stress drive`: depth.txt,
calibration.json, odometry.txt) onto a ROS master as a robot publishes it:

- /tf_static: base_link -> CAMERA_FRAME, the camera mount (--mount "x y z qx qy qz qw"), latched;
- /odom (nav_msgs/Odometry, frame odom, child base_link) and /tf odom -> base_link: each odometry.txt sample
  (T_camera_to_odom, the camera's optical frame in the base's odometry frame) less the mount;
- /camera/depth/image (32FC1 metres, NaN for no reading) and /camera/depth/camera_info (latched).

All stamped with the sequence's own times (the depth's clock). The first depth frame goes out alone (the
daemon's push source sizes its pipeline on it and only then opens its socket, as in test_ros_tf_tree); once
--wait-socket exists, the rest follows at the recorded pace times --speed, the base's odometry --lead-s ahead of
the depth (the bridge looks odom -> base_link up at each frame's stamp, so it must be there before the frame's
pose comes back). After the last frame it writes --done-file and waits for SIGINT/SIGTERM (the latched mount
stays).

Needs the Debian packages python3-rospy, python3-nav-msgs, python3-sensor-msgs, python3-tf2-msgs, python3-pil
(not part of the build).
"""

import argparse
import array
import json
import math
import os
import signal
import sys
import time

import rospy
from geometry_msgs.msg import TransformStamped
from PIL import Image as PngImage
from nav_msgs.msg import Odometry
from sensor_msgs.msg import CameraInfo, Image
from tf2_msgs.msg import TFMessage


def quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def quat_rotate(q, v):
    x, y, z, w = quat_mul(quat_mul(q, (v[0], v[1], v[2], 0.0)), (-q[0], -q[1], -q[2], q[3]))
    return (x, y, z)


def inverse(pose):
    t, q = pose
    qi = (-q[0], -q[1], -q[2], q[3])
    ti = quat_rotate(qi, t)
    return ((-ti[0], -ti[1], -ti[2]), qi)


def compose(a, b):
    ta, qa = a
    tb, qb = b
    r = quat_rotate(qa, tb)
    q = quat_mul(qa, qb)
    n = math.sqrt(sum(c * c for c in q))
    return ((ta[0] + r[0], ta[1] + r[1], ta[2] + r[2]), tuple(c / n for c in q))


def parse_pose(values, what):
    if len(values) != 7:
        sys.exit(f"ros_fake_robot: {what}: expected 'x y z qx qy qz qw', got {values!r}")
    v = [float(x) for x in values]
    return ((v[0], v[1], v[2]), (v[3], v[4], v[5], v[6]))


def read_rows(path, width, expected, what):
    """The rows of a TUM-style list: fields split, comments and blank lines skipped; each row has `width` fields."""
    rows = []
    with open(path) as f:
        for number, line in enumerate(f, 1):
            fields = line.split()
            if not fields or fields[0].startswith('#'):
                continue
            if len(fields) != width:
                sys.exit(f"ros_fake_robot: {path}:{number}: expected '{expected}', got {line.strip()!r}")
            rows.append((number, fields))
    if not rows:
        sys.exit(f"ros_fake_robot: {path} lists no {what}")
    return rows


def read_odometry(path):
    return [(float(fields[0]), parse_pose(fields[1:], f"{path}:{number}"))
            for number, fields in read_rows(path, 8, 't tx ty tz qx qy qz qw', "samples: give a sequence's odometry.txt")]


def transform(parent, child, stamp, pose):
    m = TransformStamped()
    m.header.frame_id = parent
    m.header.stamp = stamp
    m.child_frame_id = child
    (m.transform.translation.x, m.transform.translation.y, m.transform.translation.z) = pose[0]
    (m.transform.rotation.x, m.transform.rotation.y, m.transform.rotation.z, m.transform.rotation.w) = pose[1]
    return m


def read_depth_list(sequence):
    return [(float(fields[0]), os.path.join(sequence, fields[1]))
            for _, fields in read_rows(os.path.join(sequence, 'depth.txt'), 2, 'timestamp filename', 'frames')]


def depth_message(path, stamp, depth_scale, frame_id):
    png = PngImage.open(path)
    m = Image()
    m.header.stamp = stamp
    m.header.frame_id = frame_id
    m.width, m.height = png.size
    m.encoding = '32FC1'
    m.is_bigendian = sys.byteorder == 'big'
    m.step = 4 * m.width
    nan = float('nan')
    m.data = array.array('f', (raw / depth_scale if raw else nan for raw in png.getdata())).tobytes()
    return m


def odometry_message(t, base):
    o = Odometry()
    o.header.frame_id = 'odom'
    o.header.stamp = rospy.Time.from_sec(t)
    o.child_frame_id = 'base_link'
    (o.pose.pose.position.x, o.pose.pose.position.y, o.pose.pose.position.z) = base[0]
    (o.pose.pose.orientation.x, o.pose.pose.orientation.y, o.pose.pose.orientation.z,
     o.pose.pose.orientation.w) = base[1]
    return o


def main():
    p = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    p.add_argument('--sequence', required=True, help='the synthetic drive (depth.txt, calibration.json, odometry.txt)')
    p.add_argument('--mount', default='0 0 1.2 -0.5 0.5 -0.5 0.5',
                   help="base_link -> camera: 'x y z qx qy qz qw' (default: 1.2 m up, optical axes)")
    p.add_argument('--camera-frame', default='camera_depth_optical_frame')
    p.add_argument('--speed', type=float, default=1.0, help='replay speed (1: recorded pace)')
    p.add_argument('--lead-s', type=float, default=0.5, help='seconds of odometry published ahead of the depth')
    p.add_argument('--wait-socket', required=True, help="the daemon's socket: the replay goes on once it exists")
    p.add_argument('--done-file', required=True, help='written after the last frame')
    args = p.parse_args(rospy.myargv()[1:])
    mount = parse_pose(args.mount.split(), '--mount')
    samples = read_odometry(os.path.join(args.sequence, 'odometry.txt'))
    frames = read_depth_list(args.sequence)
    calibration = json.load(open(os.path.join(args.sequence, 'calibration.json')))
    depth_scale = float(calibration['depth_scale'])

    rospy.init_node('fake_robot', disable_signals=True)
    odom_pub = rospy.Publisher('/odom', Odometry, queue_size=1000)
    tf_pub = rospy.Publisher('/tf', TFMessage, queue_size=1000)
    static_pub = rospy.Publisher('/tf_static', TFMessage, queue_size=1, latch=True)
    depth_pub = rospy.Publisher('/camera/depth/image', Image, queue_size=2)
    info_pub = rospy.Publisher('/camera/depth/camera_info', CameraInfo, queue_size=1, latch=True)
    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    signal.signal(signal.SIGINT, lambda *_: stop.append(1))
    info = CameraInfo()
    info.header.frame_id = args.camera_frame
    info.width, info.height = int(calibration['width']), int(calibration['height'])
    info.K = [calibration['fx'], 0, calibration['cx'], 0, calibration['fy'], calibration['cy'], 0, 0, 1]
    info_pub.publish(info)
    static_pub.publish(TFMessage([transform('base_link', args.camera_frame, rospy.Time.from_sec(frames[0][0] + 0.001),
                                            mount)]))
    while not stop and depth_pub.get_num_connections() == 0:
        time.sleep(0.1)
    time.sleep(1.0)  # the latched mount and CameraInfo reach the bridge
    depth_pub.publish(depth_message(frames[0][1], rospy.Time.from_sec(frames[0][0]), depth_scale, args.camera_frame))
    while not stop and not os.path.exists(args.wait_socket):
        time.sleep(0.1)
    time.sleep(1.0)  # the bridge connects to the daemon

    unmount = inverse(mount)
    start_wall = time.monotonic()
    first = frames[1][0] if len(frames) > 1 else frames[0][0]
    i, k = 0, 1  # the next odometry sample, the next depth frame
    while not stop and k < len(frames):
        replay_t = first + (time.monotonic() - start_wall) * args.speed
        batch = []
        while i < len(samples) and samples[i][0] <= replay_t + args.lead_s:
            t, camera = samples[i]
            base = compose(camera, unmount)
            odom_pub.publish(odometry_message(t, base))
            batch.append(transform('odom', 'base_link', rospy.Time.from_sec(t), base))
            i += 1
        if batch:
            tf_pub.publish(TFMessage(batch))
        if frames[k][0] <= replay_t:
            depth_pub.publish(depth_message(frames[k][1], rospy.Time.from_sec(frames[k][0]), depth_scale,
                                            args.camera_frame))
            k += 1
        time.sleep(0.005)
    print(f'fake_robot: published {k} depth frames and {i} odometry samples', flush=True)
    open(args.done_file, 'w').write(f'{k} {i}\n')
    while not stop:
        time.sleep(0.1)
    return 0


if __name__ == '__main__':
    sys.exit(main())
