"""The mission microservice against the firmware on QEMU, in lockstep (run by gcs_client.py).

pymavlink plays the ground station's side of each dialogue (it answers the vehicle's
MISSION_REQUEST_INT with the item asked for, and downloads item by item) on the default build:
- on connect, the mission list asked for as QGroundControl does: empty;
- with the mission limits raised (MIS_SPEED, MIS_ACCEL, MIS_YAW_RATE), a takeoff, a 1.6 m leg
  turning 30 degrees and a land are refused: MISSION_ACK DENIED and STATUSTEXTs naming Theorem
  2's torque condition, both sides and the slow-down that certifies;
- with the limits divided by that factor (its square for the acceleration), the same mission is
  accepted, downloaded back item for item, and cleared;
- a short mission is uploaded and flown: the motion-capture pose follows the vehicle's
  reference (POSITION_TARGET_LOCAL_NED, a vehicle that tracks it exactly) until every item is
  reported reached (MISSION_ITEM_REACHED, in order).
"""

import math

from gcs_client import C, VEHICLE_COMPONENT, VEHICLE_SYSTEM, command_long, fly, sender

END_US = 20_000_000


def item(mav, seq, command, ned, hold=0.0, yaw_deg=math.nan):
    """MISSION_ITEM_INT `seq` in MAV_FRAME_LOCAL_NED (x, y in metres x 1e4, z down)."""
    return mav.mission_item_int_encode(
        VEHICLE_SYSTEM, VEHICLE_COMPONENT, seq, C.MAV_FRAME_LOCAL_NED, command, 0, 1,
        hold, 0.0, 0.0, yaw_deg, round(ned[0] * 1e4), round(ned[1] * 1e4), ned[2],
    )


def missions(elf, check):
    print("missions (the default build): upload refused and accepted, download, clear, flight")
    gcs = sender()
    three = [
        item(gcs, 0, C.MAV_CMD_NAV_TAKEOFF, (0.0, 0.0, -2.0)),
        item(gcs, 1, C.MAV_CMD_NAV_WAYPOINT, (1.5, -0.5, -2.0), yaw_deg=30.0),
        item(gcs, 2, C.MAV_CMD_NAV_LAND, (1.5, -0.5, 0.0)),
    ]
    # Flown at the slowed limits. Not shorter: at a given peak acceleration a shorter leg has
    # a larger jerk and snap (they grow as 1/sqrt(length)), so it is harder to certify.
    short = [
        item(gcs, 0, C.MAV_CMD_NAV_TAKEOFF, (0.0, 0.0, -2.0)),
        item(gcs, 1, C.MAV_CMD_NAV_WAYPOINT, (0.0, 0.0, -2.0), hold=0.5),
        item(gcs, 2, C.MAV_CMD_NAV_LAND, (0.0, 0.0, 0.0)),
    ]
    state = {"upload": None, "download": [], "factor": None, "target": (0.0, 0.0, 0.0)}
    received = []

    def pack(m):
        return m.pack(gcs)

    def upload(items):
        def start():
            state["upload"] = items
            return pack(gcs.mission_count_encode(VEHICLE_SYSTEM, VEHICLE_COMPONENT, len(items)))
        return start

    def param_set(name, value):
        return pack(gcs.param_set_encode(VEHICLE_SYSTEM, VEHICLE_COMPONENT, name.encode(),
                                         value, C.MAV_PARAM_TYPE_REAL32))

    def limits(c):
        return [
            (f"MIS_SPEED {1.0 / c}", lambda: param_set("MIS_SPEED", 1.0 / c)),
            (f"MIS_ACCEL {1.0 / c**2}", lambda: param_set("MIS_ACCEL", 1.0 / c ** 2)),
            (f"MIS_YAW_RATE {0.15 / c}", lambda: param_set("MIS_YAW_RATE", 0.15 / c)),
        ]

    def slowed():
        """The limits divided by the factor the refusal offered."""
        c = state["factor"] or 1.0
        return b"".join(f() for _, f in limits(c))

    def respond(m):
        t = m.get_type()
        if t == "MISSION_REQUEST_INT" and state["upload"] is not None:
            items = state["upload"]
            return pack(items[m.seq]) if m.seq < len(items) else b""
        if t == "MISSION_ACK":
            state["upload"] = None
        if t == "MISSION_COUNT" and state["download"] is not None and m.count > 0:
            state["download"] = []
            state["download_count"] = m.count
            return pack(gcs.mission_request_int_encode(VEHICLE_SYSTEM, VEHICLE_COMPONENT, 0))
        if t == "MISSION_ITEM_INT" and state["download"] is not None:
            state["download"].append(m)
            if len(state["download"]) < state.get("download_count", 0):
                return pack(gcs.mission_request_int_encode(
                    VEHICLE_SYSTEM, VEHICLE_COMPONENT, len(state["download"])))
            return pack(gcs.mission_ack_encode(VEHICLE_SYSTEM, VEHICLE_COMPONENT,
                                               C.MAV_MISSION_ACCEPTED))
        if t == "STATUSTEXT" and "slower certifies" in m.text and state["factor"] is None:
            state["factor"] = float(m.text.split(";")[1].split("x")[0])
        if t == "POSITION_TARGET_LOCAL_NED":
            state["target"] = (m.x, m.y, m.z)
        return b""

    request_list = lambda: pack(gcs.mission_request_list_encode(VEHICLE_SYSTEM, VEHICLE_COMPONENT))
    script = [
        (150_000, "MISSION_REQUEST_LIST on connect", request_list),
        (200_000, "PARAM_SET MIS_SPEED 1", lambda: param_set("MIS_SPEED", 1.0)),
        (210_000, "PARAM_SET MIS_ACCEL 1", lambda: param_set("MIS_ACCEL", 1.0)),
        (220_000, "PARAM_SET MIS_YAW_RATE 0.15", lambda: param_set("MIS_YAW_RATE", 0.15)),
        (300_000, "upload, too fast", upload(three)),
        (500_000, "limits slowed by the offered factor", slowed),
        (600_000, "upload, slowed", upload(three)),
        (700_000, "download", request_list),
        (900_000, "MISSION_CLEAR_ALL",
         lambda: pack(gcs.mission_clear_all_encode(VEHICLE_SYSTEM, VEHICLE_COMPONENT))),
        (950_000, "MISSION_REQUEST_LIST after the clear", request_list),
        (1_000_000, "upload the short mission", upload(short)),
        (1_300_000, "arm", lambda: command_long(gcs, C.MAV_CMD_COMPONENT_ARM_DISARM, 1.0)),
        (1_350_000, "MISSION_START", lambda: command_long(gcs, C.MAV_CMD_MISSION_START)),
    ]
    rx = C.MAVLink(None)
    rx.robust_parsing = True

    def reached():
        return [m.seq for _, m in received if m.get_type() == "MISSION_ITEM_REACHED"]

    fly(elf, script, END_US, rx, received, pose=lambda t: state["target"], respond=respond,
        until=lambda: len(reached()) >= len(short))

    def between(kind, t0, t1):
        return [m for t, m in received if m.get_type() == kind and t0 <= t < t1]

    counts = between("MISSION_COUNT", 150_000, 200_000)
    check([m.count for m in counts] == [0], f"on connect: the mission list is empty "
          f"({[m.count for m in counts]})")
    acks = between("MISSION_ACK", 300_000, 500_000)
    check([a.type for a in acks] == [C.MAV_MISSION_DENIED],
          f"too fast: MISSION_ACK DENIED ({[a.type for a in acks]})")
    texts = [m.text for m in between("STATUSTEXT", 300_000, 500_000)]
    check(len(texts) == 2 and texts[0].startswith("mission denied: theorem2.torque_max_")
          and "vs" in texts[1] and "slower certifies" in texts[1],
          f"too fast: the condition, both sides and the slow-down named ({texts})")
    acks = between("MISSION_ACK", 600_000, 700_000)
    check([a.type for a in acks] == [C.MAV_MISSION_ACCEPTED],
          f"slowed by {state['factor']}: the same path accepted ({[a.type for a in acks]})")
    down = state["download"] or []
    same = [(d.seq, d.command, d.frame, d.x, d.y, d.z) for d in down] == [
        (i.seq, i.command, i.frame, i.x, i.y, i.z) for i in three]
    check(same, f"download: the three items as uploaded ({len(down)} items)")
    acks = between("MISSION_ACK", 900_000, 950_000)
    counts = between("MISSION_COUNT", 950_000, 1_000_000)
    check([a.type for a in acks] == [C.MAV_MISSION_ACCEPTED] and [m.count for m in counts] == [0],
          f"clear: accepted, then the list is empty ({[a.type for a in acks]}, "
          f"{[m.count for m in counts]})")
    acks = between("MISSION_ACK", 1_000_000, 1_300_000)
    check([a.type for a in acks] == [C.MAV_MISSION_ACCEPTED],
          f"the short mission accepted ({[a.type for a in acks]})")
    modes = {m.custom_mode for m in between("HEARTBEAT", 1_400_000, END_US)}
    check(5 in modes, f"flying the uploaded mission: HEARTBEAT custom_mode 5 ({modes})")
    check(reached() == [0, 1, 2], f"each item reached, in order ({reached()})")
    current = [m.seq for m in between("MISSION_CURRENT", 1_350_000, END_US)]
    check(current[:1] == [0] and 1 in current and 2 in current,
          f"MISSION_CURRENT follows the items ({current})")
