#!/usr/bin/env python3
"""QGroundControl's connect sequence, played with pymavlink against a vehicle on UDP.

The vehicle is `host-sim sil --gcs-udp 127.0.0.1:PORT` or `host-sim pil --gcs-udp
127.0.0.1:PORT`: it sends its telemetry to PORT, where this script listens (`udpin`, as
QGroundControl on 14550), and it takes frames back on the port they come from. The steps, each
printed with `ok` or `FAIL`:

1. wait for the vehicle's HEARTBEAT (a vehicle type, an autopilot other than INVALID); from
   then on send a GCS HEARTBEAT every second, as QGroundControl does;
2. PARAM_REQUEST_LIST, then collect PARAM_VALUE until every index of param_count is in; when
   the stream goes quiet with indices missing, ask for each with PARAM_REQUEST_READ by index
   (QGroundControl's retry), a few times at most;
3. MISSION_REQUEST_LIST for mission_type MISSION (0), FENCE (1) and RALLY (2), each answered by
   a MISSION_COUNT of that type; a count of 0 is acknowledged with MISSION_ACK (accepted), a
   count above 0 is downloaded with MISSION_REQUEST_INT item by item, then acknowledged, as
   QGroundControl does. The request is repeated on a timeout, a few times at most.

Exit status 0 when every step passes, 1 at the first failure (with what was missing and how
long it waited), 2 on bad usage. Usage: qgc_connect.py --port PORT [--timeout-scale K]
[--lose-every N]. The timeouts are wall-clock seconds, sized for the emulated board (PIL runs
at about a third of real time, so its 1 Hz heartbeat arrives every ~3 s); --timeout-scale
multiplies them all.
"""

import argparse
import os
import sys
import time

# MAVLink 2 from the first frame: the firmware decodes MAVLink 2 only (pymavlink defaults to 1).
os.environ["MAVLINK20"] = "1"

from pymavlink import mavutil  # noqa: E402  (after MAVLINK20 on purpose)

C = mavutil.mavlink
GCS_SYSTEM, GCS_COMPONENT = 255, 190  # QGroundControl's ids
MISSION_TYPES = [
    (C.MAV_MISSION_TYPE_MISSION, "MISSION"),
    (C.MAV_MISSION_TYPE_FENCE, "FENCE"),
    (C.MAV_MISSION_TYPE_RALLY, "RALLY"),
]


class Failed(Exception):
    """A step failed; the message says what was missing."""


class Gcs:
    """The ground station: a pymavlink UDP endpoint that listens on `port`, answers to the last
    sender, keeps its own heartbeat going, and reads only the vehicle's frames."""

    def __init__(self, port, scale, lose_every):
        self.conn = mavutil.mavlink_connection(
            f"udpin:0.0.0.0:{port}",
            source_system=GCS_SYSTEM,
            source_component=GCS_COMPONENT,
            dialect="common",
        )
        self.scale = scale
        self.lose_every = lose_every
        self.vehicle = None  # (system, component) once its heartbeat is seen
        self.last_heartbeat = 0.0
        self.param_values_seen = 0
        self.lost = 0

    def t(self, seconds):
        return seconds * self.scale

    def heartbeat_if_due(self):
        if self.vehicle is not None and time.monotonic() - self.last_heartbeat >= 1.0:
            self.conn.mav.heartbeat_send(
                C.MAV_TYPE_GCS, C.MAV_AUTOPILOT_INVALID, 0, 0, C.MAV_STATE_ACTIVE
            )
            self.last_heartbeat = time.monotonic()

    def receive(self, types, until, accept=lambda m: True):
        """The next message of one of `types` from the vehicle that `accept`s, or None at the
        monotonic time `until`. Keeps the heartbeat going while it waits."""
        while True:
            self.heartbeat_if_due()
            left = until - time.monotonic()
            if left <= 0:
                return None
            m = self.conn.recv_match(type=types, blocking=True, timeout=min(left, 0.2))
            if m is None or m.get_type() == "BAD_DATA":
                continue
            if self.vehicle is not None and (
                m.get_srcSystem(), m.get_srcComponent()
            ) != self.vehicle:
                continue
            if m.get_type() == "PARAM_VALUE" and self.lose_every:
                # A lossy link, on purpose, so that the retry by index is exercised.
                self.param_values_seen += 1
                if self.param_values_seen % self.lose_every == 0:
                    self.lost += 1
                    continue
            if accept(m):
                return m


def step(name, fn):
    start = time.monotonic()
    try:
        detail = fn()
    except Failed as e:
        print(f"  FAIL {name}: {e} ({time.monotonic() - start:.1f} s)", flush=True)
        raise
    print(f"  ok   {name}: {detail} ({time.monotonic() - start:.1f} s)", flush=True)


def wait_heartbeat(gcs):
    timeout = gcs.t(60.0)
    m = gcs.receive(
        "HEARTBEAT",
        time.monotonic() + timeout,
        lambda m: m.type != C.MAV_TYPE_GCS and m.autopilot != C.MAV_AUTOPILOT_INVALID,
    )
    if m is None:
        raise Failed(
            f"no vehicle HEARTBEAT within {timeout:.0f} s (is host-sim sending to this port?)"
        )
    gcs.vehicle = (m.get_srcSystem(), m.get_srcComponent())
    gcs.heartbeat_if_due()
    autopilot = C.enums["MAV_AUTOPILOT"][m.autopilot].name
    vehicle_type = C.enums["MAV_TYPE"][m.type].name
    version = 2 if m.get_msgbuf()[0] == 0xFD else 1
    return (
        f"system {gcs.vehicle[0]} component {gcs.vehicle[1]}, {vehicle_type}, {autopilot}, "
        f"MAVLink {version}"
    )


def load_parameters(gcs):
    system, component = gcs.vehicle
    gcs.conn.mav.param_request_list_send(system, component)
    values = {}
    count = None
    quiet = gcs.t(3.0)  # the stream is over, or lost, after this long without a PARAM_VALUE
    rounds, max_rounds = 0, 5  # retries of the missing indices, as QGroundControl's
    reads = 0
    total = gcs.t(120.0)
    deadline = time.monotonic() + total
    while count is None or len(values) < count:
        m = gcs.receive("PARAM_VALUE", min(deadline, time.monotonic() + quiet))
        if m is not None:
            if count is None:
                count = m.param_count
                if count == 0:
                    raise Failed("param_count is 0")
            elif m.param_count != count:
                raise Failed(f"param_count changed from {count} to {m.param_count}")
            if 0 <= m.param_index < count:
                values[m.param_index] = (m.param_id, m.param_value)
            continue
        if time.monotonic() >= deadline:
            raise Failed(
                f"{len(values)} of {count} parameters after {total:.0f} s"
            )
        if count is None:
            if rounds >= max_rounds:
                raise Failed(
                    f"no PARAM_VALUE after {rounds + 1} PARAM_REQUEST_LIST, "
                    f"{quiet:.0f} s each"
                )
            rounds += 1
            gcs.conn.mav.param_request_list_send(system, component)
            continue
        missing = [i for i in range(count) if i not in values]
        if rounds >= max_rounds:
            raise Failed(
                f"{len(values)} of {count} parameters; indices {missing} still missing after "
                f"{rounds} rounds of PARAM_REQUEST_READ"
            )
        rounds += 1
        for i in missing:
            gcs.conn.mav.param_request_read_send(system, component, b"", i)
            reads += 1
    names = sorted(v[0] for v in values.values())
    return (
        f"{count} parameters ({', '.join(names[:3])}, ...); {gcs.lost} lost on purpose, "
        f"{reads} PARAM_REQUEST_READ by index"
    )


def mission_download(gcs, mission_type, label):
    system, component = gcs.vehicle
    attempts, per_attempt = 3, gcs.t(5.0)

    def request_until(send, types, accept, what):
        for attempt in range(attempts):
            send()
            m = gcs.receive(types, time.monotonic() + per_attempt, accept)
            if m is not None:
                return m
        raise Failed(
            f"no {what} after {attempts} requests, {per_attempt:.0f} s each (does the vehicle "
            "speak the MAVLink mission protocol?)"
        )

    def is_ack_or(kind):
        return lambda m: getattr(m, "mission_type", 0) == mission_type and (
            m.get_type() == kind or m.get_type() == "MISSION_ACK"
        )

    def refused(m):
        result = C.enums["MAV_MISSION_RESULT"][m.type].name
        return Failed(f"the vehicle answered MISSION_ACK {result} for {label}")

    m = request_until(
        lambda: gcs.conn.mav.mission_request_list_send(system, component, mission_type),
        ["MISSION_COUNT", "MISSION_ACK"],
        is_ack_or("MISSION_COUNT"),
        f"MISSION_COUNT for mission_type {label} ({mission_type})",
    )
    if m.get_type() == "MISSION_ACK":
        raise refused(m)
    count = m.count
    for seq in range(count):
        item = request_until(
            lambda: gcs.conn.mav.mission_request_int_send(system, component, seq, mission_type),
            ["MISSION_ITEM_INT", "MISSION_ITEM", "MISSION_ACK"],
            lambda m: getattr(m, "mission_type", 0) == mission_type
            and (m.get_type() == "MISSION_ACK" or m.seq == seq),
            f"item {seq} of {count} ({label})",
        )
        if item.get_type() == "MISSION_ACK":
            raise refused(item)
    # QGroundControl acknowledges every download, the empty one included.
    gcs.conn.mav.mission_ack_send(system, component, C.MAV_MISSION_ACCEPTED, mission_type)
    return f"MISSION_COUNT {count}" + (", items downloaded" if count else "") + ", MISSION_ACK sent"


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--port", type=int, required=True, help="UDP port to listen on (udpin)")
    p.add_argument("--timeout-scale", type=float, default=1.0, help="multiplies every timeout")
    p.add_argument(
        "--lose-every",
        type=int,
        default=0,
        help="drop every N-th PARAM_VALUE on receipt (0: none), to exercise the retries",
    )
    a = p.parse_args()
    if a.timeout_scale <= 0 or a.lose_every < 0:
        p.error("--timeout-scale must be > 0 and --lose-every >= 0")
    gcs = Gcs(a.port, a.timeout_scale, a.lose_every)
    print(f"QGroundControl's connect sequence on udpin:0.0.0.0:{a.port}", flush=True)
    try:
        step("vehicle HEARTBEAT", lambda: wait_heartbeat(gcs))
        step("parameters (PARAM_REQUEST_LIST)", lambda: load_parameters(gcs))
        for mission_type, label in MISSION_TYPES:
            step(
                f"mission_type {label} (MISSION_REQUEST_LIST)",
                lambda t=mission_type, n=label: mission_download(gcs, t, n),
            )
    except Failed:
        return 1
    print("all steps passed", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
