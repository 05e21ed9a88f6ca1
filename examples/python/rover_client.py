#!/usr/bin/env python3
"""A PC program for Blodwen that is not hostctl: Python's standard library only.

It talks to the rover's serial port exactly as the original PC library does, written from
the wire's reference (sections 2-4 and 8) and nothing of this project's code: its own
register tables, its own float32 value mapping, its own frames. So it shows that a program
written for the real rover drives the twin unchanged; `--print-frames` prints the frames it
builds and `--print-mapping` its float32 mapping of section 3's examples, which the tests
compare with the reference's bytes and values.

    python3 examples/python/rover_client.py --port /tmp/rover        # drive, report
    python3 examples/python/rover_client.py --print-frames           # frames, no port
    python3 examples/python/rover_client.py --print-mapping          # section 3's examples

Driving: open the port (the master resets and sends its banner), wait for `Ready`, set the
library's read sets, calibrate(), resetExceptions(), all six drives to 1000 ticks/s, wheel 1
steered to 40 degrees and lifted to 20, then Rover::update() every 10 ms until every demand
is met for 10 updates in a row (or --timeout seconds pass); then every drive to 0 until the
wheels stop. The report on stdout (lines, or one JSON object with --json) says what the
rover's boards reported.
"""

import argparse
import fcntl
import json
import os
import select
import struct
import sys
import termios
import time

# --- Register tables (reference section 2): id -> (bytes, writable, range or None) -------

# The writable column mirrors section 2; the library does not check it (the original master
# dropped a write to a read-only register and still answered 00; this master refuses the
# whole frame with 89, docs/protocol.md).
W, R = True, False
COMMON = [
    (1, W, None),  # 0 RESET
    (2, R, None),  # 1 TIMER
    (2, R, None),  # 2 INTERVALI2C
    (2, R, None),  # 3 STATUS
    (1, W, None),  # 4 DEBUGLED
    (2, W, None),  # 5 EXCEPTIONDATA
    (2, W, None),  # 6 DISABLEDEXCEPTIONS
    (1, W, None),  # 7 PING
    (2, W, None),  # 8 DEBUG
]
# A position motor's first 14 registers, the same on a steer (DS ids 26-39) and a lift
# (LL ONE ids 9-22, TWO ids 27-40).
POSITION_HEAD = [
    (2, W, (-200, 200)),  # +0 REQPOS
    (2, W, (0, 100)),  # +1 PGAIN
    (2, W, (0, 10)),  # +2 IGAIN
    (2, W, (-10, 10)),  # +3 DGAIN
    (2, W, (0, 1000)),  # +4 INTEGRALCAP
    (2, W, (0, 1)),  # +5 INTEGRALDECAY
    (2, W, (0, 1000)),  # +6 OVERCURRENTTHRESH
    (2, R, (-200, 200)),  # +7 ACTUALPOS
    (2, R, (-200, 200)),  # +8 ERROR
    (2, R, (-1000, 1000)),  # +9 ERRORINTEGRAL
    (2, R, (-200, 200)),  # +10 ERRORDERIV
    (2, R, (-255, 255)),  # +11 CONTROL
    (2, R, (0, 1000)),  # +12 INTERVALCTRL
    (2, R, None),  # +13 CURRENT
]
STALLCHECK, DEADZONE, CALIB = (1, W, (0, 255)), (1, W, (0, 50)), (1, W, (-120, 120))
DS = (
    COMMON
    + [
        (2, W, (-4000, 4000)),  # 9 DRIVE_REQSPEED
        (2, W, (0, 10)),  # 10 DRIVE_PGAIN
        (2, W, (0, 10)),  # 11 DRIVE_IGAIN
        (2, W, (-10, 10)),  # 12 DRIVE_DGAIN
        (2, W, (0, 1000)),  # 13 DRIVE_INTEGRALCAP
        (2, W, (0, 1)),  # 14 DRIVE_INTEGRALDECAY
        (2, W, (0, 1000)),  # 15 DRIVE_OVERCURRENTTHRESH
        (2, R, (-4000, 4000)),  # 16 DRIVE_ACTUALSPEED
        (2, R, (-1000, 1000)),  # 17 DRIVE_ERROR
        (2, R, (-1000, 1000)),  # 18 DRIVE_ERRORINTEGRAL
        (2, R, (-200, 200)),  # 19 DRIVE_ERRORDERIV
        (2, R, (-255, 255)),  # 20 DRIVE_CONTROL
        (2, R, (0, 1000)),  # 21 DRIVE_INTERVALCTRL
        (2, R, None),  # 22 DRIVE_CURRENT
        (2, R, None),  # 23 DRIVE_ODO
        STALLCHECK,  # 24 DRIVE_STALLCHECK
        DEADZONE,  # 25 DRIVE_DEADZONE
    ]
    + POSITION_HEAD  # 26-39 STEER_REQPOS .. STEER_CURRENT
    + [STALLCHECK, DEADZONE, CALIB, CALIB]  # 40-43: STALLCHECK DEADZONE CALIBMIN CALIBMAX
    + [(2, R, (0, 1024))]  # 44 CHASSIS
)
# The lift block orders its last four unlike the steer's (section 2.3).
LIFT_BLOCK = POSITION_HEAD + [CALIB, CALIB, STALLCHECK, DEADZONE]  # +14 .. +17
LL = COMMON + LIFT_BLOCK + LIFT_BLOCK  # TWO = ONE + 18
MASTER = [(1, W, None)] + [(2, R, (-20, 100))] * 10 + [(2, R, None)]
assert len(DS) == 45 and len(LL) == 45 and len(MASTER) == 12


def table_of(device):
    """The register table of a device: the master, a lift board (3, 6, 9) or a DS board."""
    if device == 0:
        return MASTER
    return LL if device % 3 == 0 else DS


# --- Value mapping in float32 (reference section 3) -----------------------------------


def f32(x):
    """x rounded to the nearest float32, as every step of the original's maths is."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def to_raw(value, size, span):
    """map(): a value to its raw register value."""
    if span is None:
        return int(value) & 0xFFFF
    lo, hi = span
    full = 2 ** (8 * size) - 2
    v = min(max(f32(value), lo), hi)
    return int(f32(f32(f32(v - lo) * full) / (hi - lo)))


def from_raw(raw, size, span):
    """unmap(): a raw register value to its value."""
    if span is None:
        return float(raw)
    lo, hi = span
    full = 2 ** (8 * size) - 2
    return f32(f32(f32(raw * f32(hi - lo)) / full) + lo)


class RoverError(Exception):
    """What the library would throw: a comms, range or constraint error."""


# --- Frames (reference section 4.2) ---------------------------------------------------


def write_frame(device, writes):
    """Command 2: k writes of (id, value) as the device's table sizes and maps them."""
    table = table_of(device)
    body = [len(writes)]
    for reg, value in writes:
        if reg >= len(table):
            raise RoverError(f"{reg} is not a sensible register")
        size, _, span = table[reg]
        if span is not None and not span[0] <= value <= span[1]:
            raise RoverError(f"{value:f} out of range for register {reg}")
        raw = to_raw(value, size, span)
        body += [reg] + list(raw.to_bytes(2, "little")[:size])
    if len(body) + 2 > 255:
        raise RoverError("message too long")
    return bytes([len(body) + 2, device << 4 | 2] + body)


def set_read_set_frame(device, index, ids):
    """Command 4: read set `index` holds `ids`."""
    if len(ids) > 24:
        raise RoverError("read set too large")
    return bytes([len(ids) + 3, device << 4 | 4, index] + ids)


def read_frame(device, index):
    """Command 3: read set `index` from `device`."""
    return bytes([3, device << 4 | 3, index])


# The library's read sets (reference section 4.3).
SET_DS = [1, 2, 3, 5, 44, 16, 17, 18, 19, 20, 21, 22, 23, 33, 34, 35, 36, 37, 38, 39]
SET_LL = [1, 2, 3, 5, 16, 17, 18, 19, 20, 21, 22, 34, 35, 36, 37, 38, 39, 40]
SET_MASTER = list(range(1, 12))
SETS = {0: SET_DS, 1: SET_LL, 2: SET_MASTER}


def controllers(pair):
    """Pair p's boards: DS 3p+1 (its odd wheel), DS 3p+2 (its even wheel), LL 3p+3."""
    return 3 * pair + 1, 3 * pair + 2, 3 * pair + 3


def init_frames(mask):
    """init(): the read sets via each present pair's boards, then set 2 via the master."""
    frames = []
    for pair in range(3):
        if mask >> pair & 1:
            first, second, lift = controllers(pair)
            frames += [
                (first, set_read_set_frame(first, 0, SET_DS)),
                (second, set_read_set_frame(second, 0, SET_DS)),
                (lift, set_read_set_frame(lift, 1, SET_LL)),
            ]
    frames.append((0, set_read_set_frame(0, 2, SET_MASTER)))
    return frames


# --- The PC-side parameter blocks and calibrate() (reference section 8) -----------------

# Per wheel 1..6: steer min/max, lift min/max, as calibrate() sends them.
CALIBRATION = {
    1: (-56, 66, -109, 109),
    2: (-62, 59, -102, 112),
    3: (-59, 64, -110, 105),
    4: (-60, 65, -101, 110),
    5: (-66, 57, -113, 113),
    6: (-62, 60, -109, 103),
}


class Block:
    """One motor's parameters as the PC keeps them (section 8.2's defaults)."""

    def __init__(self):
        self.p = self.i = self.d = self.cap = self.decay = 0.0
        self.overcurrent, self.stall, self.deadzone = 10.0, 255.0, 1.0
        self.calib = (-100.0, 100.0)


def wheel_boards(wheel):
    """Wheel w's DS board, and its LL board with the block offset (0 ONE, 18 TWO)."""
    pair, odd = (wheel - 1) // 2, wheel % 2 == 1
    first, second, lift = controllers(pair)
    return (first if odd else second), lift, (0 if odd else 18)


def drive_params(b):
    """sendParams for a drive: ids 10 11 12 13 14 15 24 25."""
    values = [b.p, b.i, b.d, b.cap, b.decay, b.overcurrent, b.stall, b.deadzone]
    return list(zip([10, 11, 12, 13, 14, 15, 24, 25], values))


def steer_params(b):
    """sendParams for a steer: ids 27 28 29 30 31 32 42 43 40 41."""
    values = [b.p, b.i, b.d, b.cap, b.decay, b.overcurrent]
    values += [b.calib[0], b.calib[1], b.stall, b.deadzone]
    return list(zip([27, 28, 29, 30, 31, 32, 42, 43, 40, 41], values))


def lift_params(b, offset):
    """sendParams for a lift: ids 10 11 12 13 14 15 23 24 25 26, +18 for TWO."""
    values = [b.p, b.i, b.d, b.cap, b.decay, b.overcurrent]
    values += [b.calib[0], b.calib[1], b.stall, b.deadzone]
    ids = [10, 11, 12, 13, 14, 15, 23, 24, 25, 26]
    return [(reg + offset, v) for reg, v in zip(ids, values)]


class Library:
    """The library's state: parameter blocks and the last demands, per wheel."""

    def __init__(self):
        self.drive = {w: Block() for w in CALIBRATION}
        self.steer = {w: Block() for w in CALIBRATION}
        self.lift = {w: Block() for w in CALIBRATION}

    def calibrate_steps(self, wheel):
        """calibrate() for one wheel: (device, frame) or ("wait", seconds), in order."""
        ds, ll, offset = wheel_boards(wheel)
        smin, smax, lmin, lmax = CALIBRATION[wheel]
        d = self.drive[wheel]
        d.p, d.i, d.d, d.cap, d.decay, d.overcurrent = 0.01, 0, 0, 0, 0, 500
        steps = [(ds, write_frame(ds, drive_params(d)))]
        s = self.steer[wheel]
        s.calib, s.cap, s.decay = (smin, smax), 0, 0
        steps += [(ds, write_frame(ds, steer_params(s))), ("wait", 0.05)]
        s.p, s.i, s.d, s.cap, s.decay, s.overcurrent = 0, 2, 0, 300, 0.95, 500
        s.deadzone = 0.5
        steps.append((ds, write_frame(ds, steer_params(s))))
        lift = self.lift[wheel]
        lift.calib, lift.cap, lift.decay = (lmin, lmax), 0, 0
        steps += [(ll, write_frame(ll, lift_params(lift, offset))), ("wait", 0.05)]
        lift.p, lift.i, lift.d, lift.cap, lift.decay, lift.overcurrent = 0, 5, 0, 50, 0.9, 500
        steps.append((ll, write_frame(ll, lift_params(lift, offset))))
        return steps

    def required(self, wheel, motor, value):
        """setRequired: the (device, frame) of a demand, after the PC-side limits."""
        ds, ll, offset = wheel_boards(wheel)
        if motor == "drive":
            return ds, write_frame(ds, [(9, value)])
        block = self.steer[wheel] if motor == "steer" else self.lift[wheel]
        lo, hi = block.calib
        if value > hi - 10 or value < lo + 10:
            raise RoverError("required position out of range")
        if motor == "steer":
            return ds, write_frame(ds, [(26, value)])
        return ll, write_frame(ll, [(9 + offset, value)])


def reset_frames(mask):
    """resetExceptions(): REG_RESET = 1 to each present pair's boards, then the master."""
    frames = []
    for pair in range(3):
        if mask >> pair & 1:
            frames += [(c, write_frame(c, [(0, 1)])) for c in controllers(pair)]
    return frames + [(0, write_frame(0, [(0, 1)]))]


# --- The serial port (reference section 4.1) -------------------------------------------


class Port:
    """The master's serial port: 115200 8N1 raw, request and reply."""

    def __init__(self, path):
        try:
            self.fd = os.open(path, os.O_RDWR | os.O_NOCTTY)
        except OSError as e:
            raise RoverError(
                f"cannot open {path}: {e.strerror} (give the rover's serial port, or start"
                f" the twin with `twin --link {path}`)"
            ) from e
        attrs = termios.tcgetattr(self.fd)
        attrs[0] = 0  # iflag: no translation, no flow control
        attrs[1] = 0  # oflag: raw output
        attrs[2] = termios.CS8 | termios.CREAD | termios.CLOCAL | termios.HUPCL
        attrs[3] = 0  # lflag: no echo, no canonical lines, no signals
        attrs[4] = attrs[5] = termios.B115200
        attrs[6][termios.VMIN], attrs[6][termios.VTIME] = 1, 0
        termios.tcsetattr(self.fd, termios.TCSANOW, attrs)
        self.pulse_dtr()
        termios.tcflush(self.fd, termios.TCIFLUSH)

    def pulse_dtr(self):
        """DTR down for 10 ms and up again: the Uno's auto-reset, so the banner follows
        even when DTR was already up. A pty refuses it (the twin resets on the open)."""
        dtr = struct.pack("I", termios.TIOCM_DTR)
        try:
            fcntl.ioctl(self.fd, termios.TIOCMBIC, dtr)
            time.sleep(0.01)
            fcntl.ioctl(self.fd, termios.TIOCMBIS, dtr)
        except OSError:
            pass

    def read(self, count, timeout):
        """Exactly `count` bytes, or RoverError after `timeout` seconds without one."""
        data = b""
        while len(data) < count:
            ready, _, _ = select.select([self.fd], [], [], timeout)
            if not ready:
                raise RoverError("time out in read")
            chunk = os.read(self.fd, count - len(data))
            if not chunk:  # hung up: select would report it readable forever
                raise RoverError("the port closed")
            data += chunk
        return data

    def banner(self):
        """The lines up to `Ready` (at most 10, 5 s each), as the library waits for them."""
        lines = []
        for _ in range(10):
            line, deadline = b"", time.monotonic() + 5.0
            while not line.endswith(b"\n"):
                line += self.read(1, max(0.0, deadline - time.monotonic()))
            lines.append(line.replace(b"\r", b"").rstrip(b"\n").decode("ascii", "replace"))
            if lines[-1] == "Ready":
                return lines
        raise RoverError(f"no Ready in the banner: {lines}")

    def transact(self, frame, reply_len):
        """Sends a frame and reads its reply (1 s per read, as the library's select())."""
        os.write(self.fd, frame)
        return self.read(reply_len, 1.0)

    def close(self):
        os.close(self.fd)


def reply_len(device, index):
    """A read set's reply length, from the addressed device's table."""
    table = table_of(device)
    return sum(table[reg][0] for reg in SETS[index])


def decode(device, index, reply):
    """A read set's reply as {id: value}, little-endian, unmapped per the device's table."""
    table, values, at = table_of(device), {}, 0
    for reg in SETS[index]:
        size, _, span = table[reg]
        raw = int.from_bytes(reply[at : at + size], "little")
        values[reg] = from_raw(raw, size, span)
        at += size
    return values


class Rover:
    """A connected rover: the library's calls over one port."""

    def __init__(self, port, mask=7):
        self.port, self.mask, self.lib = port, mask, Library()
        self.values = {}

    def write(self, frame):
        reply = self.port.transact(frame, 1)
        if reply != b"\x00":
            raise RoverError(f"error in reg write: {reply[0]}")

    def init(self):
        for device, frame in init_frames(self.mask):
            count = self.port.transact(frame, 1)[0]
            if count != frame[0] - 3:
                raise RoverError(f"error in read set: {count}, should be {frame[0] - 3}")

    def calibrate(self):
        # All six wheels, whatever the mask: the writes to absent boards are answered 00.
        for wheel in CALIBRATION:
            for device, frame in self.lib.calibrate_steps(wheel):
                if device == "wait":
                    time.sleep(frame)
                else:
                    self.write(frame)

    def reset_exceptions(self):
        for _, frame in reset_frames(self.mask):
            self.write(frame)

    def set_required(self, wheel, motor, value):
        self.write(self.lib.required(wheel, motor, value)[1])

    def wheels(self):
        return [w for w in CALIBRATION if self.mask >> ((w - 1) // 2) & 1]

    def update(self):
        """Rover::update(): read set 0 or 1 from each present board, then set 2."""
        devices = [c for p in range(3) if self.mask >> p & 1 for c in controllers(p)]
        for device in devices + [0]:
            index = 2 if device == 0 else (1 if device % 3 == 0 else 0)
            reply = self.port.transact(read_frame(device, index), reply_len(device, index))
            self.values[device] = decode(device, index, reply)

    def wheel(self, wheel):
        """What the boards report for one wheel."""
        ds, ll, offset = wheel_boards(wheel)
        return {
            "wheel": wheel,
            "speed": self.values[ds][16],
            "steer": self.values[ds][33],
            "lift": self.values[ll][16 + offset],
        }

    def exceptions(self):
        """Each board in exception: its type (low byte of EXCEPTIONDATA, STATUS bit 0)."""
        found = {}
        for device, values in self.values.items():
            data = int(values[11] if device == 0 else values[5])
            in_exception = data != 0 if device == 0 else int(values[3]) & 1
            if in_exception:
                found[device] = data & 0xFF
        return found


# --- The program -------------------------------------------------------------------------


def print_frames():
    """The frames this program builds, one `name: hex` per line, for the tests to pin."""
    lib = Library()
    named = [("init " + str(d), f) for d, f in init_frames(1)]
    steps = [f for d, f in lib.calibrate_steps(1) if d != "wait"]
    named += zip(["drive", "steer 1st", "steer 2nd", "lift 1st", "lift 2nd"], steps)
    named += [("reset " + str(d), f) for d, f in reset_frames(2)]
    for wheel, motor, value in [(1, "drive", 1000), (1, "drive", 0), (1, "steer", 40)]:
        named.append((f"{motor} {wheel} {value}", lib.required(wheel, motor, value)[1]))
    for wheel in (1, 2):
        named.append((f"lift {wheel} 20", lib.required(wheel, "lift", 20)[1]))
    named.append(("read master", read_frame(0, 2)))
    for name, frame in named:
        print(f"{name}: {frame.hex(' ')}")


# Section 3's worked examples and raw values above F: (register, device's table, id, value).
MAPPING_EXAMPLES = [
    ("DRIVE_REQSPEED", DS, 9, [1000, 0, -1000, -4000, 4000, 1300, 5000]),
    ("STEER_REQPOS", DS, 26, [40, -40]),
    ("STEER_CALIBMIN", DS, 42, [-56, 66]),
    ("DRIVE_PGAIN", DS, 10, [0.01]),
    ("STEER_IGAIN", DS, 28, [2]),
    ("INTEGRALDECAY", DS, 14, [0.95, 0.9]),
    ("INTEGRALCAP", DS, 13, [300, 50]),
    ("OVERCURRENTTHRESH", DS, 15, [500, 200, 10]),
    ("STALLCHECK", DS, 24, [255]),
    ("DEADZONE", DS, 25, [1, 0.5]),
    ("TEMP1", MASTER, 2, [0.0, 21.5]),
]
ABOVE_F = [
    ("DRIVE_REQSPEED", DS, 9, 65535),
    ("STALLCHECK", DS, 24, 255),
    ("STEER_CALIBMIN", DS, 42, 255),
]


def print_mapping():
    """map() and unmap() on section 3's examples, one `name value -> raw -> value` per
    line (6 decimals), then raw values above F, for the tests to pin."""
    for name, table, reg, values in MAPPING_EXAMPLES:
        size, _, span = table[reg]
        for value in values:
            raw = to_raw(value, size, span)
            print(f"{name} {value} -> {raw:#06x} -> {from_raw(raw, size, span):.6f}")
    for name, table, reg, raw in ABOVE_F:
        size, _, span = table[reg]
        print(f"{name} raw {raw:#06x} -> {from_raw(raw, size, span):.6f}")


def settled(rover, demands):
    """Every demand met: drives within 5 % but at least 20 ticks/s (so a stop has slack),
    positions within 2 degrees."""
    for wheel in rover.wheels():
        seen = rover.wheel(wheel)
        for motor, want in demands.get(wheel, {}).items():
            slack = max(0.05 * abs(want), 20.0) if motor == "speed" else 2.0
            if abs(seen[motor] - want) > slack:
                return False
    return True


def drive(path, timeout):
    port = Port(path)
    try:
        report = {"banner": port.banner()}
        time.sleep(2.0)  # as the library does after Ready
        rover = Rover(port)
        rover.init()
        rover.calibrate()
        rover.reset_exceptions()
        demands = {w: {"speed": 1000.0} for w in rover.wheels()}
        demands[1].update(steer=40.0, lift=20.0)
        for wheel in rover.wheels():
            rover.set_required(wheel, "drive", 1000)
        rover.set_required(1, "steer", 40)
        rover.set_required(1, "lift", 20)
        report["settled"] = run_until(rover, demands, 10, timeout)
        report["driving"] = [rover.wheel(w) for w in rover.wheels()]
        report["exceptions"] = rover.exceptions()
        for wheel in rover.wheels():
            rover.set_required(wheel, "drive", 0)
        stop = {w: {"speed": 0.0} for w in rover.wheels()}
        report["stopped"] = run_until(rover, stop, 3, timeout)
        report["after_stop"] = [rover.wheel(w) for w in rover.wheels()]
        return report
    finally:
        port.close()


def run_until(rover, demands, in_a_row, timeout):
    """update() every 10 ms until `demands` hold `in_a_row` updates in a row; False when
    `timeout` seconds pass first."""
    end, held = time.monotonic() + timeout, 0
    while time.monotonic() < end:
        rover.update()
        held = held + 1 if settled(rover, demands) else 0
        if held >= in_a_row:
            return True
        time.sleep(0.01)
    return False


def print_report(report):
    """The report as lines: `banner:`, `settled: yes|no`, a `wheel W:` line per wheel,
    `exceptions:`, `stopped: yes|no`, then a `wheel W after stop:` line per wheel."""
    print("banner: " + " | ".join(report["banner"]))
    print("settled: " + ("yes" if report["settled"] else "no"))
    for w in report["driving"]:
        print(wheel_line(w, ""))
    found = report["exceptions"]
    print("exceptions: " + (", ".join(f"device {d} type {t}" for d, t in found.items()) or "none"))
    print("stopped: " + ("yes" if report["stopped"] else "no"))
    for w in report["after_stop"]:
        print(wheel_line(w, " after stop"))


def wheel_line(w, when):
    return (
        f"wheel {w['wheel']}{when}: speed {w['speed']:.1f} ticks/s,"
        f" steer {w['steer']:.2f} deg, lift {w['lift']:.2f} deg"
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--port", help="the rover's serial port (or the twin's link)")
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds per phase")
    parser.add_argument("--json", action="store_true", help="the report as one JSON object")
    parser.add_argument("--print-frames", action="store_true", help="print frames, no port")
    parser.add_argument("--print-mapping", action="store_true", help="print map() examples")
    args = parser.parse_args()
    if args.print_frames:
        print_frames()
        return 0
    if args.print_mapping:
        print_mapping()
        return 0
    if not args.port:
        parser.error("give --port PATH (the twin prints its pty path, or use its --link)")
    try:
        report = drive(args.port, args.timeout)
        if args.json:
            print(json.dumps(report))
        else:
            print_report(report)
    except (RoverError, OSError) as e:
        print(f"rover_client: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
