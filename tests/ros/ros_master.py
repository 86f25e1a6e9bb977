#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-only
"""ctest fixture for the ROS tests: a real rosmaster on 127.0.0.1 with a free port.

  ros_master.py start DIR   starts `rosmaster --core -p PORT`, waits until it answers XML-RPC,
                            writes DIR/master.env (ROS_MASTER_URI=..., ROS_MASTER_PID=...)
  ros_master.py stop DIR    stops that rosmaster by its PID and removes master.env
"""
import os
import signal
import socket
import subprocess
import sys
import time
import xmlrpc.client


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start(d):
    os.makedirs(d, exist_ok=True)
    stop(d)  # a master left over from an interrupted run
    port = free_port()
    uri = "http://127.0.0.1:%d/" % port
    env = dict(os.environ, ROS_IP="127.0.0.1", ROS_MASTER_URI=uri, ROS_HOME=d, ROS_LOG_DIR=d)
    env.pop("ROS_HOSTNAME", None)
    log = open(os.path.join(d, "rosmaster.log"), "w")
    # Own session and no inherited pipes: ctest does not wait for it, and it outlives this script.
    p = subprocess.Popen(["rosmaster", "--core", "-p", str(port)], env=env, stdin=subprocess.DEVNULL,
                         stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    deadline = time.monotonic() + 15
    while True:
        if p.poll() is not None:
            sys.exit("rosmaster exited with %d (see %s/rosmaster.log)" % (p.returncode, d))
        try:
            code, _, pid = xmlrpc.client.ServerProxy(uri).getPid("/fixture")
            if code == 1:
                break
        except OSError:
            pass
        if time.monotonic() > deadline:
            p.kill()
            sys.exit("rosmaster on %s did not answer within 15 s" % uri)
        time.sleep(0.05)
    with open(os.path.join(d, "master.env"), "w") as f:
        f.write("ROS_MASTER_URI=%s\nROS_MASTER_PID=%d\n" % (uri, p.pid))
    print("rosmaster pid %d on %s" % (p.pid, uri))


def stop(d):
    path = os.path.join(d, "master.env")
    if not os.path.exists(path):
        return
    pid = None
    for line in open(path):
        if line.startswith("ROS_MASTER_PID="):
            pid = int(line.split("=", 1)[1])
    os.remove(path)
    if pid is None:
        return
    try:
        os.kill(pid, signal.SIGTERM)
    except ProcessLookupError:
        return
    for _ in range(100):
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            break
        time.sleep(0.05)
    else:
        os.kill(pid, signal.SIGKILL)
    print("stopped rosmaster pid %d" % pid)


if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[1] not in ("start", "stop"):
        sys.exit(__doc__)
    (start if sys.argv[1] == "start" else stop)(sys.argv[2])
