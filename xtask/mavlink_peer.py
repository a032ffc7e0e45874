"""The autopilot and the target for the MAVLink guidance endpoint, played with pymavlink (the
protocol's reference implementation), on the firmware's UART in QEMU.

    python mavlink_peer.py serve PORT [KEY]
                                          JSON requests on stdin, one answer per line on stdout;
                                          with KEY (64 hex digits), MAVLink 2 signing both ways
    python mavlink_peer.py session PORT   the scripted session: every message kind, parameter
                                          and malformed input; one line per check, exit 1 if any fails

`cargo xtask run --link mavlink` drives `serve` (its simulator integrates the vehicles and plays
the evader); `cargo xtask test` runs both. The endpoint's contract is restated in
docs/mavlink.md.
"""
import json
import math
import os
import random
import sys
import time

os.environ["MAVLINK20"] = "1"
from pymavlink import mavutil  # noqa: E402

mavlink = mavutil.mavlink
UNIT = (1, 191)          # our system (TC_SYSID) and component
OWN = (1, 1)             # the autopilot
TARGET = (2, 1)          # the target vehicle (TC_TGT_SYSID)
GCS = (255, 190)
HOME = (473977420, 85455940)
QUIET = 0.3              # seconds to wait where the unit must stay silent


class Peer:
    def __init__(self, port):
        self.conn = mavutil.mavlink_connection(f"tcp:127.0.0.1:{port}", source_system=255,
                                               source_component=190, retries=40)
        self.conn.WIRE_PROTOCOL_VERSION = "2.0"
        self.received = []

    def send_as(self, sender, message):
        self.conn.mav.srcSystem, self.conn.mav.srcComponent = sender
        self.conn.mav.send(message)

    def raw(self, data):
        self.conn.write(bytes(data))

    def recv(self, timeout):
        """The next message from the unit, or None after `timeout` seconds."""
        deadline = time.monotonic() + timeout
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            m = self.conn.recv_match(blocking=True, timeout=left)
            if m is None:
                return None
            if m.get_type() == "BAD_DATA":
                raise AssertionError(f"the unit sent bytes pymavlink cannot parse: {m}")
            self.received.append(m)
            return m

    def wait(self, kind, timeout=2.0, where=lambda m: True):
        """The first message of `kind` matching `where`; the others seen meanwhile."""
        seen = []
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            m = self.recv(deadline - time.monotonic())
            if m is None:
                break
            if m.get_type() == kind and where(m):
                return m, seen
            seen.append(m)
        return None, seen

    def collect(self, seconds):
        out = []
        deadline = time.monotonic() + seconds
        while True:
            m = self.recv(deadline - time.monotonic())
            if m is None:
                return out
            out.append(m)

    def position(self, sender, time_ms, fix, velocity_cm_s, hdg):
        lat, lon = fix
        vx, vy = velocity_cm_s
        self.send_as(sender, mavlink.MAVLink_global_position_int_message(
            time_ms, lat, lon, 100000, 10000, vx, vy, 0, hdg))

    def param_set(self, name, value):
        self.send_as(GCS, mavlink.MAVLink_param_set_message(
            UNIT[0], UNIT[1], name.encode(), value, mavlink.MAV_PARAM_TYPE_REAL32))
        reply, seen = self.wait("PARAM_VALUE", where=lambda m: m.param_id == name)
        texts = [m for m in seen if m.get_type() == "STATUSTEXT"]
        more, _ = self.wait("STATUSTEXT", timeout=0.1)
        if more is not None:
            texts.append(more)
        return reply, texts

    def step(self, own, target, timeout=2.0):
        """One control period: the target's and the own state; the setpoint and TC_T (waited
        for `timeout` seconds)."""
        if target is not None:
            self.position(TARGET, *target)
        self.position(OWN, *own)
        out = {}
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and len(out) < 2:
            m = self.recv(deadline - time.monotonic())
            if m is None:
                break
            kind = m.get_type()
            if kind == "SET_ATTITUDE_TARGET":
                out["setpoint"] = {
                    "target": [m.target_system, m.target_component],
                    "type_mask": m.type_mask, "q": list(m.q),
                    "yaw_rate": m.body_yaw_rate, "thrust": m.thrust}
            elif kind == "NAMED_VALUE_FLOAT" and m.name == "TC_T":
                out["tc_t"] = m.value
        return out


def serve(port, key=None):
    """JSON requests: {"op": "heartbeat"} (the first heartbeat and the STATUSTEXTs around it),
    {"op": "set", "name", "value"}, {"op": "list"},
    {"op": "step", "own": [time_ms, [lat, lon], [vx, vy], hdg], "target": [...]},
    {"op": "target", "target": [...]} (a target fix alone), {"op": "quiet", "seconds"} and,
    where signing is on,
    {"op": "refusals", "name", "value", "kept"}."""
    peer = Peer(port)
    if key is not None:
        # Signed both ways; a signed heartbeat first, from which the unit (no real-time
        # clock) takes its signing clock before its own frames can pass our check.
        peer.conn.setup_signing(bytes.fromhex(key), sign_outgoing=True, link_id=1)
        peer.send_as(GCS, mavlink.MAVLink_heartbeat_message(
            mavlink.MAV_TYPE_GCS, mavlink.MAV_AUTOPILOT_INVALID, 0, 0, 0, 3))
    for line in sys.stdin:
        request = json.loads(line)
        op = request["op"]
        if op == "heartbeat":
            m, seen = peer.wait("HEARTBEAT", timeout=3.0)
            texts = [t.text for t in seen + peer.collect(0.3) if t.get_type() == "STATUSTEXT"]
            answer = None if m is None else {
                "system": m.get_srcSystem(), "component": m.get_srcComponent(),
                "type": m.type, "autopilot": m.autopilot, "version": m.mavlink_version,
                "texts": texts}
        elif op == "set":
            m, texts = peer.param_set(request["name"], request["value"])
            answer = None if m is None else {"name": m.param_id, "value": m.param_value,
                                             "texts": [t.text for t in texts]}
        elif op == "list":
            peer.send_as(GCS, mavlink.MAVLink_param_request_list_message(*UNIT))
            values = []
            while True:
                m, _ = peer.wait("PARAM_VALUE", timeout=1.0)
                if m is None:
                    break
                values.append([m.param_id, m.param_value, m.param_index, m.param_count])
                if len(values) == m.param_count:
                    break
            answer = values
        elif op == "step":
            answer = peer.step(request["own"], request.get("target"))
        elif op == "target":
            peer.position(TARGET, *request["target"])
            answer = {}
        elif op == "quiet":
            time.sleep(request["seconds"])
            peer.collect(0.05)
            answer = {}
        elif op == "refusals":
            answer = refusals(peer, request["name"], request["value"], request["kept"])
        else:
            answer = {"error": f"unknown op {op}"}
        print(json.dumps(answer), flush=True)


SIGNATURE_COUNTERS = ("TC_BADFRM", "TC_NOSIG", "TC_BADSIG", "TC_OLDSIG")


def signature_counters(peer, before=None, timeout=2.5):
    """The unit's counters from its next heartbeat group (the first that differs from
    `before`, where given)."""
    deadline = time.monotonic() + timeout
    counts = {}
    while time.monotonic() < deadline:
        m, _ = peer.wait("NAMED_VALUE_FLOAT", timeout=deadline - time.monotonic(),
                         where=lambda m: m.name in SIGNATURE_COUNTERS)
        if m is None:
            break
        counts[m.name] = m.value
        if m.name == SIGNATURE_COUNTERS[-1]:
            if before is None or counts != before:
                return counts
            counts = {}
    return counts or None


def refusals(peer, name, value, kept):
    """Where signing is on: a PARAM_SET of `name` to `value` unsigned, under a wrong key,
    replayed, with a timestamp gone back and with its signature cut short; each must go
    unanswered and count once. Then `name` read back (`kept` expected) and pymavlink's own
    verdict on every frame the unit signed."""
    signing = peer.conn.mav.signing
    param_set = mavlink.MAVLink_param_set_message(
        UNIT[0], UNIT[1], name.encode(), value, mavlink.MAV_PARAM_TYPE_REAL32)
    peer.conn.mav.srcSystem, peer.conn.mav.srcComponent = GCS

    def unsigned():
        signing.sign_outgoing = False
        peer.raw(param_set.pack(peer.conn.mav))
        signing.sign_outgoing = True

    def wrong_key():
        key, signing.secret_key = signing.secret_key, bytes(range(100, 132))
        peer.raw(param_set.pack(peer.conn.mav))
        signing.secret_key = key

    def replayed():
        # A signed PARAM_SET to the value the parameter has, taken and answered; then the
        # same bytes again.
        taken = mavlink.MAVLink_param_set_message(
            UNIT[0], UNIT[1], name.encode(), kept, mavlink.MAV_PARAM_TYPE_REAL32)
        frame = taken.pack(peer.conn.mav)
        peer.raw(frame)
        reply, _ = peer.wait("PARAM_VALUE", timeout=1.0, where=lambda m: m.param_id == name)
        if reply is None:
            raise AssertionError("the signed original of the replay was not answered")
        peer.raw(frame)

    def gone_back():
        now = signing.timestamp
        signing.timestamp = now - 100_000  # one second back
        peer.raw(param_set.pack(peer.conn.mav))
        signing.timestamp = now + 1

    def truncated():
        # Six bytes short: the line's next six complete its signature, which fails. They are
        # zeros, not the start of a frame: a frame's rest would be noise to the unit, and a
        # 0xFD among its random signature bytes reads as a frame start and counts a second
        # bad frame.
        frame = param_set.pack(peer.conn.mav)
        peer.raw(frame[:-6])
        peer.raw(bytes(6))

    counts = signature_counters(peer)
    cases = []
    for case, send, counter in [("unsigned", unsigned, "TC_NOSIG"),
                                ("wrong key", wrong_key, "TC_BADSIG"),
                                ("replayed", replayed, "TC_OLDSIG"),
                                ("timestamp gone back", gone_back, "TC_OLDSIG"),
                                ("signature truncated", truncated, "TC_BADSIG")]:
        send()
        reply, _ = peer.wait("PARAM_VALUE", timeout=0.5, where=lambda m: m.param_id == name)
        after = signature_counters(peer, counts) or {}
        rose = {k: after.get(k, 0) - counts.get(k, 0) for k in SIGNATURE_COUNTERS}
        # Counted once, in its own counter and in TC_BADFRM, and nowhere else.
        counted = rose == {k: float(k in (counter, "TC_BADFRM")) for k in SIGNATURE_COUNTERS}
        cases.append({"case": case, "answered": reply is not None, "counter": counter,
                      "counted": counted, "now": after.get(counter)})
        counts = after or counts
    peer.send_as(GCS, mavlink.MAVLink_param_request_read_message(
        UNIT[0], UNIT[1], name.encode(), -1))
    read, _ = peer.wait("PARAM_VALUE", where=lambda m: m.param_id == name)
    return {"cases": cases, "value": None if read is None else read.param_value,
            "unit_frames": {"good": signing.goodsig_count, "bad": signing.badsig_count,
                            "unsigned": signing.unsigned_count}}


# --- the scripted session -------------------------------------------------------------------

FAILURES = []


def check(name, condition, detail=""):
    print(f"  {'ok  ' if condition else 'FAIL'} {name}{': ' + str(detail) if detail else ''}",
          flush=True)
    if not condition:
        FAILURES.append(name)


def fix(north, east):
    """degE7 of a point `north`, `east` metres from home (a spherical step is plenty here)."""
    lat = HOME[0] + round(north / 6378137.0 * 180 / math.pi * 1e7)
    lon = HOME[1] + round(east / (6378137.0 * math.cos(math.radians(HOME[0] * 1e-7)))
                          * 180 / math.pi * 1e7)
    return lat, lon


def session(port):
    peer = Peer(port)
    print("scripted MAVLink session against the firmware in QEMU", flush=True)

    h, _ = peer.wait("HEARTBEAT", timeout=3.0)
    check("heartbeat from (1, 191): onboard controller, autopilot invalid",
          h is not None and (h.get_srcSystem(), h.get_srcComponent(), h.type, h.autopilot)
          == (1, 191, mavlink.MAV_TYPE_ONBOARD_CONTROLLER, mavlink.MAV_AUTOPILOT_INVALID),
          h)
    beats = [m for m in peer.collect(3.2) if m.get_type() == "HEARTBEAT"]
    check("heartbeat at 1 Hz (3 or 4 in 3.2 s)", len(beats) in (3, 4), len(beats))

    peer.send_as(GCS, mavlink.MAVLink_param_request_list_message(*UNIT))
    values = []
    for _ in range(16):
        m, _ = peer.wait("PARAM_VALUE", timeout=1.0)
        if m is not None:
            values.append(m)
    want = {"TC_V_PM": 2, "TC_W_PM": 2, "TC_V_EM": 1, "TC_W_EM": 1, "TC_TGT_SYSID": 2,
            "TC_VEHICLE": 0, "TC_POLICY": 1, "TC_TIMEOUT": 1, "TC_SYSID": 1, "TC_CAPTURE": 0,
            "TC_PERIOD": 0, "TC_TGT_LAG": 0, "TC_TGT_SIG": 0, "TC_TGT_SIGH": 0, "TC_LEAD": 0,
            "TC_BANK_EFF": 1}
    got = {m.param_id: m.param_value for m in values}
    check("PARAM_REQUEST_LIST: sixteen REAL32 parameters at their defaults",
          got == want and all(m.param_count == 16 and m.param_type ==
                              mavlink.MAV_PARAM_TYPE_REAL32 for m in values), got)
    peer.send_as(GCS, mavlink.MAVLink_param_request_read_message(*UNIT, b"TC_TIMEOUT", -1))
    m, _ = peer.wait("PARAM_VALUE", timeout=1.0)
    check("PARAM_REQUEST_READ by name", m is not None and m.param_id == "TC_TIMEOUT"
          and m.param_value == 1.0, m)
    peer.send_as(GCS, mavlink.MAVLink_param_request_read_message(*UNIT, b"", 8))
    m, _ = peer.wait("PARAM_VALUE", timeout=1.0)
    check("PARAM_REQUEST_READ by index", m is not None and m.param_id == "TC_SYSID"
          and m.param_index == 8, m)
    m, texts = peer.param_set("TC_TIMEOUT", 0.5)
    check("PARAM_SET TC_TIMEOUT 0.5 taken", m is not None and m.param_value == 0.5 and not texts,
          m)
    for name, value, kept in [("TC_V_EM", 3.0, 1.0), ("TC_VEHICLE", 5.0, 0.0),
                              ("TC_SYSID", 1.5, 1.0), ("TC_W_PM", float("nan"), 2.0)]:
        m, texts = peer.param_set(name, value)
        check(f"PARAM_SET {name} {value} refused: old value and a WARNING",
              m is not None and m.param_value == kept and len(texts) == 1
              and texts[0].severity == mavlink.MAV_SEVERITY_WARNING,
              (m and m.param_value, [t.text for t in texts]))

    # Positions before the first fix (0, 0) and an unknown heading: no setpoint.
    peer.position(TARGET, 0, (0, 0), (0, 0), 9000)
    r = peer.step((0, (0, 0), (0, 0), 9000), None, QUIET)
    check("own position before the first fix: no setpoint", "setpoint" not in r, r)
    r = peer.step((10, HOME, (0, 0), 65535), (10, fix(40, 30), (100, 0), 0), QUIET)
    check("own heading unknown and standing still: no setpoint", "setpoint" not in r, r)

    t = 100
    r = peer.step((t, HOME, (200, 0), 0), (t, fix(40, 30), (100, 0), 0))
    sp = r.get("setpoint", {})
    check("a setpoint: SET_ATTITUDE_TARGET to (1, 1), yaw rate and thrust used, thrust 1",
          sp.get("target") == [1, 1] and sp.get("type_mask") == 1 | 2 | 128
          and sp.get("thrust") == 1.0 and math.isfinite(sp.get("yaw_rate", math.nan)), r)
    check("TC_T: a finite predicted capture time", math.isfinite(r.get("tc_t", math.inf)), r)

    m, _ = peer.param_set("TC_VEHICLE", 1)
    t += 100
    r = peer.step((t, HOME, (200, 0), 0), (t, fix(40, 30), (100, 0), 0))
    sp = r.get("setpoint", {})
    q = sp.get("q", [1, 0, 0, 0])
    roll = math.atan2(2 * (q[0] * q[1] + q[2] * q[3]), 1 - 2 * (q[1] ** 2 + q[2] ** 2))
    check("fixed wing: attitude used, rates ignored, a bank angle",
          sp.get("type_mask") == 1 | 2 | 4 and abs(roll) > 0.01, (sp.get("type_mask"), roll))
    peer.param_set("TC_VEHICLE", 0)

    # FOLLOW_TARGET as the target, from any system: a target elsewhere, another TC_T.
    t += 100
    before = peer.step((t, HOME, (200, 0), 0), (t, fix(40, 30), (100, 0), 0)).get("tc_t")
    peer.send_as((7, 1), mavlink.MAVLink_follow_target_message(
        t, 1 | 2, *fix(10, 10), 20.0, [1.0, 0.0, 0.0], [0, 0, 0], [1, 0, 0, 0], [0, 0, 0],
        [0, 0, 0], 0))
    t += 100
    r = peer.step((t, HOME, (200, 0), 0), None)
    check("FOLLOW_TARGET as the target: its own capture time",
          "setpoint" in r and abs(r.get("tc_t", 0) - before) > 10.0, (before, r.get("tc_t")))

    # A jump of kilometres: held until confirmed.
    t += 100
    r = peer.step((t, HOME, (200, 0), 0), (t, fix(4000, 3000), (100, 0), 0), QUIET)
    check("a target jumping 5 km: no setpoint", "setpoint" not in r, r)
    t += 100
    r = peer.step((t, HOME, (200, 0), 0), (t, fix(4000.5, 3000), (100, 0), 0))
    check("the jump confirmed by the next fix: setpoints resume", "setpoint" in r, r)

    # Stale target: one WARNING, silence, then INFO when it is fresh again.
    time.sleep(0.6)
    msgs = peer.collect(0.1)
    warnings = [m for m in msgs if m.get_type() == "STATUSTEXT"
                and m.severity == mavlink.MAV_SEVERITY_WARNING]
    check("target older than TC_TIMEOUT: one WARNING", len(warnings) == 1,
          [m.text for m in warnings])
    silent = True
    mark = len(peer.received)
    for _ in range(5):
        t += 100
        silent &= "setpoint" not in peer.step((t, HOME, (200, 0), 0), None, QUIET)
    more = [m.text for m in peer.received[mark:] if m.get_type() == "STATUSTEXT"
            and m.severity == mavlink.MAV_SEVERITY_WARNING]
    check("stale: no setpoint, and no second WARNING", silent and not more, more)
    t += 100
    peer.position(TARGET, t, fix(4000, 3000), (100, 0), 0)
    r = peer.step((t, HOME, (200, 0), 0), None)
    texts = [m for m in peer.received[-4:] if m.get_type() == "STATUSTEXT"]
    check("fresh again: an INFO and setpoints",
          "setpoint" in r and any(m.severity == mavlink.MAV_SEVERITY_INFO for m in texts),
          [m.text for m in texts])

    # Malformed input: bad CRC, truncated, unknown and MAVLink 1 messages, noise; NaN fields.
    def bad_frames():
        m, _ = peer.wait("NAMED_VALUE_FLOAT", timeout=1.5, where=lambda m: m.name == "TC_BADFRM")
        return None if m is None else m.value
    dropped_before = bad_frames()
    good = mavlink.MAVLink_global_position_int_message(t, *HOME, 0, 0, 200, 0, 0, 0)
    peer.conn.mav.srcSystem, peer.conn.mav.srcComponent = OWN
    frame = bytearray(good.pack(peer.conn.mav))
    frame[-1] ^= 0xFF
    peer.raw(frame)
    peer.raw(frame[:9])
    peer.send_as(OWN, mavlink.MAVLink_attitude_message(t, 0, 0, 0, 0, 0, 0))
    rng = random.Random(29)
    peer.raw(bytes(rng.randrange(256) for _ in range(3000)))
    peer.send_as((7, 1), mavlink.MAVLink_follow_target_message(
        t, 1 | 8, *fix(40, 30), 20.0, [0, 0, 0], [0, 0, 0], [math.nan] * 4, [0, 0, 0],
        [0, 0, 0], 0))
    peer.collect(0.3)
    t += 100
    r = peer.step((t, HOME, (200, 0), 0), (t, fix(4000, 3000), (100, 0), 0))
    check("after bad CRC, truncation, unknown messages, noise and NaN: still serving",
          "setpoint" in r and math.isfinite(r["setpoint"]["yaw_rate"]), r)
    dropped_after = bad_frames()
    check("dropped frames counted (TC_BADFRM grew by at least the bad CRC)",
          dropped_before is not None and dropped_after is not None
          and dropped_after >= dropped_before + 1, (dropped_before, dropped_after))
    peer.send_as(GCS, mavlink.MAVLink_param_request_read_message(*UNIT, b"TC_TIMEOUT", -1))
    m, _ = peer.wait("PARAM_VALUE", timeout=1.0)
    check("no reset: TC_TIMEOUT still 0.5", m is not None and m.param_value == 0.5, m)
    t += 100
    peer.position(TARGET, t, fix(4000, 3000), (100, 0), 0)
    legacy = mavlink.MAVLink_global_position_int_message(t, *HOME, 0, 0, 200, 0, 0, 0)
    peer.conn.mav.srcSystem, peer.conn.mav.srcComponent = OWN
    peer.raw(legacy.pack(peer.conn.mav, force_mavlink1=True))
    m, _ = peer.wait("SET_ATTITUDE_TARGET", timeout=1.0)
    check("a MAVLink 1 own state is answered", m is not None, m)

    print(f"scripted session: {len(FAILURES)} of the checks failed" if FAILURES
          else "scripted session: every check passed", flush=True)
    return 1 if FAILURES else 0


if __name__ == "__main__":
    mode, port = sys.argv[1], int(sys.argv[2])
    if mode == "serve":
        serve(port, sys.argv[3] if len(sys.argv) > 3 else None)
    else:
        sys.exit(session(port))
