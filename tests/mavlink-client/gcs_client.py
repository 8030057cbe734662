#!/usr/bin/env python3
"""A real MAVLink client against the firmware on QEMU (mps2-an386), in lockstep.

pymavlink plays the ground station (system 255, component 190) and the motion-capture bridge:
it feeds the firmware a HIL_SENSOR every millisecond of simulated time (a vehicle at rest,
level, on the ground) and an ATT_POS_MOCAP every 10 ms, waits for each control tick's
HIL_ACTUATOR_CONTROLS, and sends a script of commands at fixed simulated times. It then
asserts what docs/mavlink.md promises.

Two builds, since who may set the signing key is fixed at build time (docs/mavlink.md,
"Signing"): the default build, whose UART is untrusted like a radio, where a stranger's
SETUP_SIGNING is refused and the owner keeps the vehicle; and the same build with
FIRMWARE_MAVLINK_LINK_TRUST=trusted (a wired console), which flies the whole script, setting
up signing over the link.

Usage: gcs_client.py <firmware-mps2-an386 ELF> <the same built with a trusted link>.
Exit status 0 when every check passes; each check is printed.
"""

import os
import queue
import subprocess
import sys
import tempfile
import threading
import time

from pymavlink.dialects.v20 import common as mavlink2

GCS_SYSTEM, GCS_COMPONENT = 255, 190
VEHICLE_SYSTEM, VEHICLE_COMPONENT = 1, 1
TICK_US = 10_000  # the default build's law runs at 100 Hz
END_US = 1_700_000
STRANGER_END_US = 300_000
KEY = bytes(range(1, 33))
WRONG_KEY = bytes([0x5A] * 32)
STRANGER_KEY = bytes([0x66] * 32)
STRANGER_SYSTEM = 66
GRAVITY = 9.80665
TIMEOUT_S = 30.0

C = mavlink2


class Qemu:
    """The firmware on QEMU, its UART 0 on our pipes, its defmt log in a file."""

    def __init__(self, elf, log_path):
        args = [
            "qemu-system-arm", "-machine", "mps2-an386", "-cpu", "cortex-m4",
            "-display", "none", "-monitor", "none", "-serial", "stdio",
            "-icount", "shift=3,align=off,sleep=on",
            "-semihosting-config", "enable=on,target=native,chardev=defmt",
            "-chardev", f"file,id=defmt,path={log_path}", "-kernel", elf,
        ]
        self.proc = subprocess.Popen(
            args, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL
        )
        self.chunks = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        fd = self.proc.stdout.fileno()
        while True:
            data = os.read(fd, 4096)
            if not data:
                self.chunks.put(None)
                return
            self.chunks.put(data)

    def send(self, data):
        self.proc.stdin.write(data)
        self.proc.stdin.flush()

    def receive(self, timeout):
        try:
            return self.chunks.get(timeout=timeout)
        except queue.Empty:
            return b""

    def stop(self):
        self.proc.kill()
        self.proc.wait()


def sender(key=None, timestamp=0, system=GCS_SYSTEM):
    """A pymavlink encoder as the ground station, signing with `key` when given."""
    m = C.MAVLink(None, srcSystem=system, srcComponent=GCS_COMPONENT)
    if key is not None:
        m.signing.secret_key = key
        m.signing.sign_outgoing = True
        m.signing.link_id = 0
        m.signing.timestamp = timestamp
    return m


def command_long(mav, command, p1=0.0, p2=0.0, p7=0.0, component=VEHICLE_COMPONENT):
    return mav.command_long_encode(
        VEHICLE_SYSTEM, component, command, 0, p1, p2, 0, 0, 0, 0, p7
    ).pack(mav)


def command_int(mav, command, p1=0.0):
    return mav.command_int_encode(
        VEHICLE_SYSTEM, VEHICLE_COMPONENT, C.MAV_FRAME_LOCAL_NED, command, 0, 0,
        p1, 0, 0, 0, 0, 0, 0.0,
    ).pack(mav)


def fly(elf, script, end_us, rx, received, on_sent=lambda label: None, pose=None,
        respond=None, until=None):
    """Runs `elf` in QEMU in lockstep until `end_us` of simulated time [µs], sending the
    sensors, the poses and at their times the frames of `script` ((time, label, function
    giving the bytes), the function called then, so it may read what came back so far);
    calls `on_sent(label)` after each. Appends what comes back, parsed by `rx`, to
    `received` as it comes, as (tick [µs] of the actuator frame before it, message).
    `pose(t)` gives the pose's position (NED [m]; the origin when absent), `respond(m)` the
    bytes to send the next millisecond in answer to a received message (a ground station's
    side of a dialogue), and the run stops at the first tick where `until()` is true."""
    stream = sender()  # sensors and poses, unsigned throughout (accepted by default)
    events = {}
    for t, label, frame in script:
        events.setdefault(t, []).append((label, frame))
    tick = 0
    log = tempfile.NamedTemporaryFile(prefix="defmt-", suffix=".bin", delete=False)
    log.close()
    qemu = Qemu(elf, log.name)
    started = time.monotonic()
    ticks = 0
    answers = bytearray()
    try:
        for t in range(0, end_us + 1, 1000):
            out = answers
            answers = bytearray()
            for label, frame in events.get(t, []):
                out += frame()
                on_sent(label)
            if t % TICK_US == 0:
                x, y, z = pose(t) if pose else (0.0, 0.0, 0.0)
                out += stream.att_pos_mocap_encode(t, [1.0, 0.0, 0.0, 0.0], x, y, z).pack(stream)
            out += stream.hil_sensor_encode(
                t, 0.0, 0.0, -GRAVITY, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 20.0, 0x3F
            ).pack(stream)
            qemu.send(bytes(out))
            if t % TICK_US:
                continue
            deadline = time.monotonic() + TIMEOUT_S
            answered = False
            while not answered:
                data = qemu.receive(max(0.0, deadline - time.monotonic()))
                if data is None:
                    raise SystemExit(f"QEMU exited at t = {t} us")
                if not data and time.monotonic() >= deadline:
                    raise SystemExit(f"no HIL_ACTUATOR_CONTROLS for t = {t} us in {TIMEOUT_S} s")
                for m in rx.parse_buffer(data) or []:
                    # The firmware sends each tick's actuator frame first, then that tick's
                    # telemetry: a frame belongs to the tick of the actuator frame before it
                    # (whatever chunks the bytes arrive in).
                    if m.get_type() == "HIL_ACTUATOR_CONTROLS":
                        tick = m.time_usec
                        answered |= m.time_usec == t
                    received.append((tick, m))
                    if respond:
                        answers += respond(m)
            ticks += 1
            if until and until():
                break
    finally:
        qemu.stop()
        os.unlink(log.name)
    wall = time.monotonic() - started
    print(f"pymavlink client: {t / 1e6:.2f} s simulated, {ticks} ticks answered, "
          f"{len(received)} frames received, {rx.total_receive_errors} receive errors, "
          f"{wall:.1f} s wall clock")


def texts_between(received, t0, t1):
    """The STATUSTEXTs received in ticks [t0, t1) [µs]."""
    return [m.text for t, m in received if m.get_type() == "STATUSTEXT" and t0 <= t < t1]


class Check:
    def __init__(self):
        self.failed = []

    def __call__(self, ok, what):
        print(f"  {'ok  ' if ok else 'FAIL'} {what}")
        if not ok:
            self.failed.append(what)


def stranger(elf, check):
    """The default build (its UART untrusted, as a radio): a stranger on the link before the
    owner tries to install a key, unsigned and signed; neither takes, and the owner's unsigned
    commands are still answered."""
    print("untrusted link (the default build): a stranger's SETUP_SIGNING")
    gcs = sender()
    rogue = sender(system=STRANGER_SYSTEM)
    rogue_signed = sender(STRANGER_KEY, timestamp=3_000_000, system=STRANGER_SYSTEM)
    script = [
        (100_000, "stranger's unsigned SETUP_SIGNING",
         lambda: rogue.setup_signing_encode(VEHICLE_SYSTEM, VEHICLE_COMPONENT, STRANGER_KEY,
                                            1_000_000).pack(rogue)),
        (150_000, "stranger's SETUP_SIGNING signed with its own key",
         lambda: rogue_signed.setup_signing_encode(VEHICLE_SYSTEM, VEHICLE_COMPONENT,
                                                   STRANGER_KEY, 1_000_000).pack(rogue_signed)),
        (200_000, "the owner's REQUEST_MESSAGE HEARTBEAT",
         lambda: command_long(gcs, C.MAV_CMD_REQUEST_MESSAGE,
                              float(C.MAVLINK_MSG_ID_HEARTBEAT))),
    ]
    rx = C.MAVLink(None)
    rx.robust_parsing = True
    received = []
    fly(elf, script, STRANGER_END_US, rx, received)
    bad = [m for _, m in received if m.get_type() == "BAD_DATA"]
    check(rx.total_receive_errors == 0 and not bad,
          f"0 parse errors ({rx.total_receive_errors} receive errors, {len(bad)} BAD_DATA)")
    texts = texts_between(received, 100_000, 110_000)
    check(texts == ["setup_signing: unsigned on an untrusted link"],
          f"stranger's unsigned SETUP_SIGNING: refused, the reason sent ({texts})")
    texts = texts_between(received, 150_000, 160_000)
    check(not texts, f"stranger's signed SETUP_SIGNING (no key to check it): dropped ({texts})")
    acks = [m for t, m in received if m.get_type() == "COMMAND_ACK" and 200_000 <= t < 210_000]
    check(len(acks) == 1 and acks[0].result == C.MAV_RESULT_ACCEPTED
          and acks[0].command == C.MAV_CMD_REQUEST_MESSAGE,
          f"the owner's unsigned command still answered ACCEPTED "
          f"({[(a.command, a.result) for a in acks]})")
    # The signed flag as sent: pymavlink's get_signed() says "verified", and this client has
    # no key to verify with.
    flagged = [m for _, m in received if m.get_header().incompat_flags & C.MAVLINK_IFLAG_SIGNED]
    check(received and not flagged,
          f"no key installed: every vehicle frame unsigned ({len(flagged)} of {len(received)} "
          f"frames signed)")


def owner(elf, check):
    """The build with a trusted (wired) link: the whole script, signing set up over it."""
    print("trusted link (FIRMWARE_MAVLINK_LINK_TRUST=trusted): the ground station's script")
    gcs = sender()
    signed = sender(KEY, timestamp=2_000_000)
    forger = sender(WRONG_KEY, timestamp=3_000_000)
    received = []  # (tick [µs] of the actuator frame before it, message)

    def param(name):
        """The last PARAM_VALUE received for `name`."""
        values = [m for _, m in received if m.get_type() == "PARAM_VALUE" and m.param_id == name]
        if not values:
            raise SystemExit(f"no PARAM_VALUE for {name} yet")
        return values[-1].param_value

    def param_set(name, value):
        return gcs.param_set_encode(
            VEHICLE_SYSTEM, VEHICLE_COMPONENT, name.encode(), value, C.MAV_PARAM_TYPE_REAL32
        ).pack(gcs)

    def param_read(name):
        return gcs.param_request_read_encode(
            VEHICLE_SYSTEM, VEHICLE_COMPONENT, name.encode(), -1
        ).pack(gcs)

    chosen = {}

    def set_kf():
        chosen["POS_KF"] = 0.9 * param("POS_KF")
        return param_set("POS_KF", chosen["POS_KF"])

    def set_tau_z():
        chosen["LIM_TAU_Z"] = param("LIM_TAU_Z")
        return param_set("LIM_TAU_Z", 0.5 * chosen["LIM_TAU_Z"])

    # Commands at simulated times [µs]: (time, label, a function giving the bytes then).
    script = [
        (100_000, "arm while calibrating",
         lambda: command_long(gcs, C.MAV_CMD_COMPONENT_ARM_DISARM, 1.0)),
        (110_000, "arm to component 99",
         lambda: command_long(gcs, C.MAV_CMD_COMPONENT_ARM_DISARM, 1.0, component=99)),
        (120_000, "DO_REPOSITION", lambda: command_long(gcs, C.MAV_CMD_DO_REPOSITION, 1.0)),
        (130_000, "COMMAND_INT arm with param1 = 2",
         lambda: command_int(gcs, C.MAV_CMD_COMPONENT_ARM_DISARM, 2.0)),
        (140_000, "REQUEST_MESSAGE HEARTBEAT",
         lambda: command_long(gcs, C.MAV_CMD_REQUEST_MESSAGE, float(C.MAVLINK_MSG_ID_HEARTBEAT))),
        (150_000, "SET_MESSAGE_INTERVAL ATTITUDE_QUATERNION 100 ms",
         lambda: command_long(gcs, C.MAV_CMD_SET_MESSAGE_INTERVAL,
                              float(C.MAVLINK_MSG_ID_ATTITUDE_QUATERNION), 100_000.0)),
        (160_000, "arm signed while signing is off",
         lambda: command_long(forger, C.MAV_CMD_COMPONENT_ARM_DISARM, 1.0)),
        (170_000, "REQUEST_AUTOPILOT_CAPABILITIES",
         lambda: command_long(gcs, C.MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES, 1.0)),
        (175_000, "TIMESYNC", lambda: gcs.timesync_encode(0, 777_000).pack(gcs)),
        (180_000, "REQUEST_MESSAGE HOME_POSITION",
         lambda: command_long(gcs, C.MAV_CMD_REQUEST_MESSAGE,
                              float(C.MAVLINK_MSG_ID_HOME_POSITION))),
        (190_000, "DO_SET_MODE helix while disarmed",
         lambda: command_long(gcs, C.MAV_CMD_DO_SET_MODE, 1.0, 4.0)),
        (200_000, "PARAM_REQUEST_LIST",
         lambda: gcs.param_request_list_encode(VEHICLE_SYSTEM, VEHICLE_COMPONENT).pack(gcs)),
        (950_000, "PARAM_SET POS_KF to 0.9 of its value", set_kf),
        (1_000_000, "PARAM_SET LIM_TAU_Z to half its value", set_tau_z),
        (1_050_000, "PARAM_REQUEST_READ LIM_TAU_Z", lambda: param_read("LIM_TAU_Z")),
        (1_200_000, "disarm (unsigned, signing off)",
         lambda: command_long(gcs, C.MAV_CMD_COMPONENT_ARM_DISARM, 0.0)),
        (1_300_000, "SETUP_SIGNING",
         lambda: gcs.setup_signing_encode(VEHICLE_SYSTEM, VEHICLE_COMPONENT, KEY,
                                          1_000_000).pack(gcs)),
        (1_400_000, "unsigned arm with signing on",
         lambda: command_long(gcs, C.MAV_CMD_COMPONENT_ARM_DISARM, 1.0)),
        (1_410_000, "arm signed with another key",
         lambda: command_long(forger, C.MAV_CMD_COMPONENT_ARM_DISARM, 1.0)),
        (1_420_000, "arm signed with the key",
         lambda: command_long(signed, C.MAV_CMD_COMPONENT_ARM_DISARM, 1.0)),
        (1_430_000, "unsigned PARAM_SET with signing on", lambda: param_set("POS_KF", 1.0)),
        (1_440_000, "SETUP_SIGNING signed with the key while armed",
         lambda: signed.setup_signing_encode(VEHICLE_SYSTEM, VEHICLE_COMPONENT, WRONG_KEY,
                                             3_000_000).pack(signed)),
    ]

    rx = C.MAVLink(None)
    rx.robust_parsing = True
    unsigned_after_signed = []

    seen = {"signed": False, "looked_at": 0}

    def allow_unsigned(mav, msg_id):
        # Called by pymavlink for an unsigned frame once it holds the key: after the first
        # signed frame (earlier in the parse order, so already in `received`) it is a failure.
        for _, m in received[seen["looked_at"]:]:
            seen["signed"] |= m.get_signed()
        seen["looked_at"] = len(received)
        if seen["signed"]:
            unsigned_after_signed.append(msg_id)
        return True

    def on_sent(label):
        if label == "SETUP_SIGNING":
            rx.signing.secret_key = KEY
            rx.signing.allow_unsigned_callback = allow_unsigned

    fly(elf, script, END_US, rx, received, on_sent)
    bad = [m for _, m in received if m.get_type() == "BAD_DATA"]
    check(rx.total_receive_errors == 0 and not bad,
          f"0 parse errors ({rx.total_receive_errors} receive errors, {len(bad)} BAD_DATA)")
    acks = [(t, m) for t, m in received if m.get_type() == "COMMAND_ACK"]

    def acks_between(t0, t1):
        return [m for t, m in acks if t0 <= t < t1]

    def one_ack(label, t0, command, result):
        got = acks_between(t0, t0 + 10_000)
        ok = (len(got) == 1 and got[0].command == command and got[0].result == result
              and (got[0].target_system, got[0].target_component) == (GCS_SYSTEM, GCS_COMPONENT))
        names = [(C.enums["MAV_CMD"][a.command].name, C.enums["MAV_RESULT"][a.result].name,
                  a.target_system, a.target_component) for a in got]
        want = C.enums["MAV_RESULT"][result].name
        check(ok, f"{label}: one ACK {want} to {GCS_SYSTEM}/{GCS_COMPONENT} (got {names})")

    def no_ack(label, t0):
        got = acks_between(t0, t0 + 10_000)
        check(not got, f"{label}: no ACK (got {len(got)})")

    one_ack("arm while calibrating", 100_000, C.MAV_CMD_COMPONENT_ARM_DISARM,
            C.MAV_RESULT_TEMPORARILY_REJECTED)
    no_ack("arm to component 99", 110_000)
    one_ack("DO_REPOSITION", 120_000, C.MAV_CMD_DO_REPOSITION, C.MAV_RESULT_UNSUPPORTED)
    one_ack("DO_SET_MODE helix while disarmed", 190_000, C.MAV_CMD_DO_SET_MODE,
            C.MAV_RESULT_DENIED)
    one_ack("COMMAND_INT arm with param1 = 2", 130_000, C.MAV_CMD_COMPONENT_ARM_DISARM,
            C.MAV_RESULT_DENIED)
    one_ack("REQUEST_MESSAGE HEARTBEAT", 140_000, C.MAV_CMD_REQUEST_MESSAGE,
            C.MAV_RESULT_ACCEPTED)
    heartbeats = [t for t, m in received if m.get_type() == "HEARTBEAT"]
    check(any(140_000 <= t < 160_000 for t in heartbeats),
          f"the requested HEARTBEAT comes at once (heartbeats at {heartbeats} us)")
    one_ack("SET_MESSAGE_INTERVAL", 150_000, C.MAV_CMD_SET_MESSAGE_INTERVAL,
            C.MAV_RESULT_ACCEPTED)
    attitude = sum(1 for t, m in received
                   if m.get_type() == "ATTITUDE_QUATERNION" and 200_000 <= t < 1_200_000)
    position = sum(1 for t, m in received
                   if m.get_type() == "LOCAL_POSITION_NED" and 200_000 <= t < 1_200_000)
    check(attitude == 10 and position == 20,
          f"over 1 s: ATTITUDE_QUATERNION {attitude} (100 ms), LOCAL_POSITION_NED {position} (50 ms)")
    no_ack("arm signed while signing is off (dropped)", 160_000)
    one_ack("REQUEST_AUTOPILOT_CAPABILITIES", 170_000,
            C.MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES, C.MAV_RESULT_ACCEPTED)
    versions = [m for t, m in received if m.get_type() == "AUTOPILOT_VERSION"]
    check(len(versions) == 1 and versions[0].capabilities & C.MAV_PROTOCOL_CAPABILITY_MAVLINK2
          and versions[0].capabilities & C.MAV_PROTOCOL_CAPABILITY_COMMAND_INT,
          f"one AUTOPILOT_VERSION, MAVLink 2 and COMMAND_INT capable ({len(versions)})")
    syncs = [m for t, m in received if m.get_type() == "TIMESYNC"]
    # The request sent before the 175 ms sample is dated by the one before it (174 ms).
    check([(m.tc1, m.ts1) for m in syncs] == [(174_000_000, 777_000)],
          f"TIMESYNC answered with the vehicle's time and ts1 echoed "
          f"({[(m.tc1, m.ts1) for m in syncs]})")
    one_ack("REQUEST_MESSAGE HOME_POSITION", 180_000, C.MAV_CMD_REQUEST_MESSAGE,
            C.MAV_RESULT_ACCEPTED)
    homes = [t for t, m in received if m.get_type() == "HOME_POSITION"]
    check(homes == [180_000, 1_420_000],
          f"HOME_POSITION on request and at the arming, nothing else ({homes})")
    status = [m for _, m in received if m.get_type() == "SYS_STATUS"]
    check(len(status) == 2 and all(
        m.onboard_control_sensors_present & C.MAV_SYS_STATUS_SENSOR_3D_GYRO for m in status)
          and not status[0].onboard_control_sensors_health & C.MAV_SYS_STATUS_SENSOR_3D_GYRO
          and status[1].onboard_control_sensors_health & C.MAV_SYS_STATUS_SENSOR_3D_GYRO,
          "SYS_STATUS at 1 Hz: gyro present, unhealthy while calibrating, then healthy")
    ext = [m for _, m in received if m.get_type() == "EXTENDED_SYS_STATE"]
    check(len(ext) == 2 and all(m.landed_state == C.MAV_LANDED_STATE_ON_GROUND for m in ext),
          "EXTENDED_SYS_STATE at 1 Hz: on the ground")
    euler = sum(1 for t, m in received if m.get_type() == "ATTITUDE" and t < 1_000_000)
    check(euler == 20, f"ATTITUDE at 20 Hz ({euler} in the first second)")
    values = [(t, m) for t, m in received if m.get_type() == "PARAM_VALUE"]
    listed = [m for t, m in values if 200_000 <= t < 950_000]
    count = listed[0].param_count if listed else 0
    check(count >= 20 and sorted(m.param_index for m in listed) == list(range(count))
          and all(m.param_type == C.MAV_PARAM_TYPE_REAL32 for m in listed)
          and all(len(m.param_id) <= 16 for m in listed),
          f"PARAM_REQUEST_LIST: every parameter once ({len(listed)} of {count})")
    kf = [m for t, m in values if 950_000 <= t < 960_000]
    check(len(kf) == 1 and kf[0].param_id == "POS_KF"
          and abs(kf[0].param_value - chosen["POS_KF"]) <= 1e-6 * chosen["POS_KF"],
          f"PARAM_SET POS_KF (certificate still holds): the new value {chosen['POS_KF']:.6g} "
          f"answered ({[m.param_value for m in kf]})")
    tau = [m for t, m in values if 1_000_000 <= t < 1_060_000]
    texts = [m.text for t, m in received
             if m.get_type() == "STATUSTEXT" and 1_000_000 <= t < 1_010_000]
    check(len(tau) == 2 and all(m.param_value == chosen["LIM_TAU_Z"] for m in tau)
          and any("LIM_TAU_Z" in x and "theorem2" in x for x in texts),
          f"PARAM_SET LIM_TAU_Z to half (breaks Theorem 2): refused, value unchanged, "
          f"the condition named ({texts})")
    late = [m for t, m in values if t >= 1_430_000]
    check(not late, f"unsigned PARAM_SET with signing on: not answered ({len(late)})")
    one_ack("disarm, signing off", 1_200_000, C.MAV_CMD_COMPONENT_ARM_DISARM,
            C.MAV_RESULT_ACCEPTED)
    no_ack("unsigned arm with signing on", 1_400_000)
    no_ack("arm signed with another key", 1_410_000)
    one_ack("arm signed with the key", 1_420_000, C.MAV_CMD_COMPONENT_ARM_DISARM,
            C.MAV_RESULT_ACCEPTED)
    texts = texts_between(received, 1_440_000, 1_450_000)
    check(texts == ["setup_signing: signing is set up while disarmed"],
          f"SETUP_SIGNING signed with the key while armed: refused, the reason sent ({texts}); "
          f"the key unchanged (below: every frame verifies with it)")
    act = [m for t, m in received if m.get_type() == "HIL_ACTUATOR_CONTROLS"]
    check(all(not (m.mode & C.MAV_MODE_FLAG_SAFETY_ARMED) for m in act if m.time_usec < 1_420_000)
          and all(m.mode & C.MAV_MODE_FLAG_SAFETY_ARMED for m in act if m.time_usec >= 1_430_000),
          "disarmed until the signed arm, armed after it (actuator frames)")
    after = [m for t, m in received if t >= 1_320_000]
    check(after and all(m.get_signed() for m in after) and rx.signing.badsig_count == 0
          and not unsigned_after_signed,
          f"after SETUP_SIGNING every vehicle frame is signed and verifies with the key "
          f"({len(after)} frames, {rx.signing.badsig_count} bad signatures, "
          f"{len(unsigned_after_signed)} unsigned after the first signed)")
    hb = [m for _, m in received if m.get_type() == "HEARTBEAT"]
    check(hb and all(m.base_mode & C.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED for m in hb),
          "HEARTBEAT: custom mode flagged as meaningful")
    act = [m for _, m in received if m.get_type() == "HIL_ACTUATOR_CONTROLS"]
    check(act and all(m.flags & C.HIL_ACTUATOR_CONTROLS_FLAGS_LOCKSTEP for m in act),
          f"HIL_ACTUATOR_CONTROLS: LOCKSTEP flag on all {len(act)}")
    targets = [m for _, m in received if m.get_type() == "POSITION_TARGET_LOCAL_NED"]
    check(targets and all(m.type_mask == 0 for m in targets),
          "POSITION_TARGET_LOCAL_NED: type_mask 0, every field the reference's")
    sources = {(m.get_srcSystem(), m.get_srcComponent()) for _, m in received}
    check(sources == {(VEHICLE_SYSTEM, VEHICLE_COMPONENT)}, f"every frame from 1/1 ({sources})")


def main():
    import mission_client  # the mission microservice's checks (its own file)
    if len(sys.argv) != 3:
        raise SystemExit("usage: gcs_client.py <firmware-mps2-an386 ELF> "
                         "<the same built with FIRMWARE_MAVLINK_LINK_TRUST=trusted>")
    check = Check()
    stranger(sys.argv[1], check)
    owner(sys.argv[2], check)
    mission_client.missions(sys.argv[1], check)
    if check.failed:
        print(f"pymavlink client: {len(check.failed)} check(s) failed")
        return 1
    print("pymavlink client: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
