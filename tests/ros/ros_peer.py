#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-only
"""A plain rospy node using the generated nns_ros_bridge/Tensors class (tests/ros).

  ros_peer.py recv TOPIC COUNT   prints each received message as one JSON line
                                 {"tensors": [{"dims": [[label, size, stride], ...],
                                               "offset": n, "data": "<hex>"}]}
  ros_peer.py send TOPIC JSON    JSON: a list of messages, each a list of tensors given as
                                 {"type": "float32", "dims": [innermost, ...], "data": "<hex>"}
                                 (optional "label" overrides every dim label); the layout is built
                                 here the way nnstreamer-ros does (outermost first, byte strides,
                                 at least 4 dims); publishes them once a subscriber is connected
  ros_peer.py bag PATH           prints each message of a rosbag file as a JSON line like recv,
                                 with "topic" first
  ros_peer.py md5                prints the generated class's type and MD5, and the MD5 computed
                                 from std_msgs/UInt8MultiArray's as ROS does
Exits 1 after 10 s without the expected peer or messages.
"""
import hashlib
import json
import sys
import time

SIZES = {"int8": 1, "uint8": 1, "int16": 2, "uint16": 2, "int32": 4, "uint32": 4,
         "int64": 8, "uint64": 8, "float16": 2, "float32": 4, "float64": 8}


def md5():
    from nns_ros_bridge.msg import Tensors
    from std_msgs.msg import UInt8MultiArray
    # genmsg: a field of message type contributes "<md5 of that type> <field name>".
    computed = hashlib.md5(("%s tensors" % UInt8MultiArray._md5sum).encode()).hexdigest()
    print(Tensors._type, Tensors._md5sum, computed)


def layout(spec):
    from std_msgs.msg import MultiArrayDimension
    dims = list(spec["dims"]) + [1] * max(0, 4 - len(spec["dims"]))
    label = spec.get("label", spec["type"])
    out, stride = [], SIZES[spec["type"]]
    for d in dims:
        stride *= d
        out.append(MultiArrayDimension(label=label, size=d, stride=stride))
    return list(reversed(out))


def send(topic, messages):
    import rospy
    from nns_ros_bridge.msg import Tensors
    from std_msgs.msg import MultiArrayLayout, UInt8MultiArray
    rospy.init_node("ros_peer_send", anonymous=True, disable_signals=True)
    pub = rospy.Publisher(topic, Tensors, queue_size=100)
    deadline = time.monotonic() + 10
    while pub.get_num_connections() < 1:
        if time.monotonic() > deadline:
            sys.exit("send: no subscriber on %s within 10 s" % topic)
        time.sleep(0.01)
    for m in messages:
        msg = Tensors()
        for t in m:
            msg.tensors.append(UInt8MultiArray(layout=MultiArrayLayout(dim=layout(t), data_offset=0),
                                               data=bytes.fromhex(t["data"])))
        pub.publish(msg)
    time.sleep(0.5)  # let the last message leave before the node goes away
    rospy.signal_shutdown("done")


def describe(msg):
    return [{"dims": [[d.label, d.size, d.stride] for d in t.layout.dim],
             "offset": t.layout.data_offset, "data": bytes(t.data).hex()} for t in msg.tensors]


def bag(path):
    import rosbag
    for topic, msg, _ in rosbag.Bag(path).read_messages():
        print(json.dumps({"topic": topic, "type": msg._type, "tensors": describe(msg)}))


def recv(topic, count):
    import threading
    import rospy
    from nns_ros_bridge.msg import Tensors
    got, done = [], threading.Event()

    def on_msg(msg):
        got.append({"tensors": describe(msg)})
        if len(got) >= count:
            done.set()

    rospy.init_node("ros_peer_recv", anonymous=True, disable_signals=True)
    rospy.Subscriber(topic, Tensors, on_msg, queue_size=100)
    ok = done.wait(10)
    for g in got[:count]:
        print(json.dumps(g))
    sys.stdout.flush()
    rospy.signal_shutdown("done")
    if not ok:
        sys.exit("recv: %d of %d messages on %s within 10 s" % (len(got), count, topic))


if __name__ == "__main__":
    if len(sys.argv) >= 2 and sys.argv[1] == "md5":
        md5()
    elif len(sys.argv) == 3 and sys.argv[1] == "bag":
        bag(sys.argv[2])
    elif len(sys.argv) == 4 and sys.argv[1] == "recv":
        recv(sys.argv[2], int(sys.argv[3]))
    elif len(sys.argv) == 4 and sys.argv[1] == "send":
        send(sys.argv[2], json.loads(sys.argv[3]))
    else:
        sys.exit(__doc__)
