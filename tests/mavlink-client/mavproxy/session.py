#!/usr/bin/env python3
"""A scripted MAVProxy session against the firmware in the loop (host-sim sil --gcs-udp).

Starts `host-sim sil --scenario ground` (the vehicle on the ground, waiting) sending to a free
local UDP port, starts MAVProxy (pinned, requirements.txt) listening there, and types what a
person would: fetch the parameters, upload mission-global.txt (refused: no origin), set the origin
(`setorigin`), upload it again (accepted), upload mission.txt (a takeoff to 2 m, a waypoint 1.6 m away
held 1 s, a land; MAV_FRAME_LOCAL_NED) with the wp module, download it back, arm, start the
mission and see it move on from the takeoff to the next item. Each step waits for MAVProxy's own
report of it; a step that does not come within its time fails the session.

MAVProxy sends every item with a location as MISSION_ITEM_INT with x, y scaled by 10^7, the
global frames' scaling, whatever the frame; `set wp_use_mission_int 0` makes it send the float
MISSION_ITEM, whose local x, y the vehicle takes in metres (docs/mavlink.md, "Missions").

Usage: session.py <host-sim binary>. Exit status 0 when every step passed.
"""

import os
import queue
import re
import socket
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def free_udp_port():
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def main():
    if len(sys.argv) != 2:
        raise SystemExit("usage: session.py <host-sim binary>")
    host_sim = sys.argv[1]
    port = free_udp_port()
    work = tempfile.mkdtemp(prefix="mavproxy-session-")
    sim = subprocess.Popen(
        [host_sim, "sil", "--scenario", "ground",
         "--gcs-udp", f"127.0.0.1:{port}", "--out", os.path.join(work, "sil")],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    mavproxy = subprocess.Popen(
        [os.path.join(os.path.dirname(sys.executable), "mavproxy.py"),
         f"--master=udpin:127.0.0.1:{port}", "--default-modules=wp,param,cmdlong,arm,mode,misc",
         f"--state-basedir={work}"],
        stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        bufsize=1)
    lines = queue.Queue()
    transcript = []

    def read():
        for line in mavproxy.stdout:
            lines.put(line.rstrip("\n"))

    threading.Thread(target=read, daemon=True).start()

    def expect(pattern, timeout):
        """The first match of `pattern` in MAVProxy's output within `timeout` [s], or None."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            try:
                line = lines.get(timeout=max(0.0, deadline - time.monotonic()))
            except queue.Empty:
                break
            transcript.append(line)
            m = re.search(pattern, line)
            if m:
                return m
        return None

    def type_(command):
        transcript.append(f"<< {command}")
        mavproxy.stdin.write(command + "\n")
        mavproxy.stdin.flush()

    failed = []

    def step(ok, what):
        print(f"  {'ok  ' if ok else 'FAIL'} {what}")
        if not ok:
            failed.append(what)
        return ok

    print(f"MAVProxy session against host-sim sil --gcs-udp 127.0.0.1:{port}")
    try:
        step(expect(r"Detected vehicle 1:1", 30) is not None, "heartbeat: vehicle 1:1 detected")
        # MAVProxy fetches the parameters on connect.
        m = expect(r"Received (\d+) parameters", 30)
        step(m is not None and int(m.group(1)) >= 20,
             f"parameters fetched ({m.group(1) if m else 'none'})")
        type_("param show MIS_SPEED")
        step(expect(r"MIS_SPEED\s+[0-9.]+", 10) is not None, "MIS_SPEED shown")
        type_("set wp_use_mission_int 0")
        # A global mission (relative altitudes; the same path about an origin at 47 N, 8 E) is
        # refused until the local frame's origin is set, then accepted.
        type_(f"wp load {os.path.join(HERE, 'mission-global.txt')}")
        step(expect(r"MISSION_ACK: TYPE_MISSION: UNSUPPORTED_FRAME", 20) is not None,
             "a global mission without an origin: MISSION_ACK UNSUPPORTED_FRAME")
        type_("setorigin 47.0 8.0 400")
        step(expect(r"GPS_GLOBAL_ORIGIN|Setting origin", 10) is not None, "origin set")
        type_(f"wp load {os.path.join(HERE, 'mission-global.txt')}")
        step(expect(r"MISSION_ACK: TYPE_MISSION: ACCEPTED", 20) is not None,
             "the global mission accepted once the origin is set")
        type_(f"wp load {os.path.join(HERE, 'mission.txt')}")
        step(expect(r"Loaded 3 waypoints", 10) is not None, "mission.txt loaded")
        step(expect(r"Sent all 3 waypoints", 20) is not None, "3 items sent")
        step(expect(r"MISSION_ACK: TYPE_MISSION: ACCEPTED", 10) is not None,
             "the vehicle certified and accepted the mission (MISSION_ACK ACCEPTED)")
        type_("wp list")
        step(expect(r"Saved 3 waypoints", 20) is not None, "the mission downloaded back")
        type_("arm throttle")
        step(expect(r"COMMAND_ACK: COMPONENT_ARM_DISARM: ACCEPTED", 15) is not None,
             "armed (COMMAND_ACK ACCEPTED)")
        type_("long MISSION_START")
        step(expect(r"COMMAND_ACK: MISSION_START: ACCEPTED", 15) is not None,
             "mission started (COMMAND_ACK ACCEPTED)")
        # MAVProxy announces MISSION_CURRENT changes: item 1 once the takeoff (2 m at the
        # default 0.1 m/s^2, about 14 s of real time) is reached.
        step(expect(r"waypoint 1", 60) is not None,
             "flying it: the takeoff reached, MISSION_CURRENT on item 1")
        type_("exit")
    finally:
        try:
            mavproxy.stdin.close()
        except OSError:
            pass
        for p in (mavproxy, sim):
            p.terminate()
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
    if failed:
        print("MAVProxy transcript:\n" + "\n".join(transcript))
        print(f"MAVProxy session: {len(failed)} step(s) failed")
        return 1
    print("MAVProxy session: all steps passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
