#!/usr/bin/python3
"""An OSP 1.1 client in plain Python: a living document of the protocol (docs/osp.md, spec/osp.md).

    scripts/osp_example_client.py [--host 127.0.0.1] [--port 45454] [--agent NAME] [--joint Right/ShoulderYaw]
                                  [--steps 200] [--amplitude 30] [--seed 1]

Connects to an OSP server (orcs-osp), lists the agents, takes control of one (the first available, or --agent),
steps it --steps times with a sine on one joint's DesiredAngle while observing that joint's JointAngle value,
resets the simulation with a seed, and prints what it read. Standard library only; exits 1 when the server does
not answer as the protocol says, 2 on bad arguments.
"""
import argparse
import math
import socket
import struct
import sys

TIMEOUT_SECONDS = 5.0
DATAGRAM_END = 120  # every datagram the server sends ends with this byte
ANGLE_RANGE_DEGREES = 150.0  # A-Series DesiredAngle/JointAngle: raw ±150 degrees <-> normalised ±1 (aseries.md §4d)
DEFAULT_TORQUE = 0.7934  # normalised DesiredTorque of every motor after reset (raw 0.586810005)


class ProtocolError(Exception):
    pass


# ---- Encoding: byte, int32 little-endian, float32 bits little-endian, NUL-terminated ASCII string. ----

def encode(*fields):
    """fields: ("b", 5), ("i", -1), ("f", 0.5), ("s", "text")."""
    out = bytearray()
    for kind, value in fields:
        if kind == "b":
            out += struct.pack("<B", value)
        elif kind == "i":
            out += struct.pack("<i", value)
        elif kind == "f":
            out += struct.pack("<f", value)
        else:
            out += value.encode("ascii") + b"\0"
    return bytes(out)


class Reader:
    """Reads the fields of one server datagram (which ends with DATAGRAM_END) in order."""

    def __init__(self, data):
        if not data or data[-1] != DATAGRAM_END:
            raise ProtocolError(f"a server datagram without the end byte 120: {data!r}")
        self.data = data[:-1]
        self.at = 0

    def byte(self):
        self.at += 1
        return self.data[self.at - 1]

    def int(self):
        (value,) = struct.unpack_from("<i", self.data, self.at)
        self.at += 4
        return value

    def float(self):
        (value,) = struct.unpack_from("<f", self.data, self.at)
        self.at += 4
        return value

    def string(self):
        end = self.data.index(b"\0", self.at)
        text = self.data[self.at:end].decode("ascii")
        self.at = end + 1
        return text


class OspClient:
    def __init__(self, host, port):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.settimeout(TIMEOUT_SECONDS)
        self.handler = None
        # Handshake: INIT 1.1 to the server port; the ACK comes from this client's own handler port, which
        # every further datagram goes to.
        self.sock.sendto(encode(("b", 5), ("b", 1), ("b", 1)), (host, port))
        data, self.handler = self.sock.recvfrom(2048)
        if data != bytes([6, 1, 1, DATAGRAM_END]):
            raise ProtocolError(f"expected the INIT ACK 6,1,1,120, got {list(data)}")

    def send(self, *fields):
        self.sock.sendto(encode(*fields), self.handler)

    def expect(self, code):
        try:
            data, _ = self.sock.recvfrom(2048)
        except socket.timeout:
            raise ProtocolError(f"no reply within {TIMEOUT_SECONDS} s (expected code {code})") from None
        reader = Reader(data)
        got = reader.byte()
        if got != code:
            raise ProtocolError(f"expected code {code}, got {got}")
        return reader

    # 90 → 91 n, then n × 92 (each acked with 93).
    def agents(self):
        self.send(("b", 90))
        count = self.expect(91).int()
        agents = []
        for _ in range(count):
            entry = self.expect(92)
            index, agent_id, kind, available, name = (entry.int(), entry.int(), entry.string(), entry.byte(),
                                                      entry.string())
            agents.append({"index": index, "id": agent_id, "type": kind, "available": available == 1, "name": name})
            self.send(("b", 93))
        return agents

    # 95 id → 96 id nIn nOut nInfo name, then one 98 per input, output and info value (each acked with 97).
    def agent_info(self, agent_id):
        self.send(("b", 95), ("i", agent_id))
        info = self.expect(96)
        _, n_in, n_out, n_info, name = info.int(), info.int(), info.int(), info.int(), info.string()
        values = []
        for _ in range(n_in + n_out + n_info):
            entry = self.expect(98)
            values.append({"index": entry.int(), "min": entry.float(), "max": entry.float(), "name": entry.string()})
            self.send(("b", 97))
        return name, values[:n_in], values[n_in:n_in + n_out]

    # 100 id → 101 id ok.
    def take_control(self, agent_id):
        self.send(("b", 100), ("i", agent_id))
        reply = self.expect(101)
        return reply.int() == agent_id and reply.byte() == 1

    # 40 regex → 41 n, then n × 43 index valueId name path (each acked with 42).
    def value_ids(self, pattern):
        self.send(("b", 40), ("s", pattern))
        ids = {}
        for _ in range(self.expect(41).int()):
            entry = self.expect(43)
            entry.int()
            value_id, _, path = entry.int(), entry.string(), entry.string()
            ids[path] = value_id
            self.send(("b", 42))
        return ids

    # 54 n ids → 55 n ids (0 where unknown).
    def observe(self, value_ids):
        self.send(("b", 54), ("i", len(value_ids)), *[("i", v) for v in value_ids])
        reply = self.expect(55)
        return [reply.int() for _ in range(reply.int())]

    # 50 id → 51 id value.
    def get(self, value_id):
        self.send(("b", 50), ("i", value_id))
        reply = self.expect(51)
        reply.int()
        return reply.string()

    # 80 id nIn floats → 81 id at once; once every controlling client has sent its step, 85 with the outputs
    # (raw), acked with 86.
    def step(self, agent_id, inputs):
        self.send(("b", 80), ("i", agent_id), ("i", len(inputs)), *[("f", x) for x in inputs])
        self.expect(81)
        result = self.expect(85)
        result.int()
        n_out, n_info, n_events, _ = result.int(), result.int(), result.int(), result.int()
        outputs = [result.float() for _ in range(n_out)]
        for _ in range(n_info):
            result.float()  # info values: the A-Series has none
        events = [result.int() for _ in range(n_events)]
        self.send(("b", 86))
        return outputs, events

    # 70 seed → 71 at once; 75 once every controlling client asked (acked with 76).
    def reset(self, seed):
        self.send(("b", 70), ("i", seed))
        self.expect(71)
        self.expect(75)
        self.send(("b", 76))

    # 7 → 8.
    def close(self):
        self.send(("b", 7))
        self.expect(8)
        self.sock.close()


def run(arguments):
    client = OspClient(arguments.host, arguments.port)
    print(f"connected to {arguments.host}:{arguments.port}, handler port {client.handler[1]}")

    agents = client.agents()
    for agent in agents:
        state = "available" if agent["available"] else "controlled"
        print(f"agent {agent['id']}: {agent['name']} (type {agent['type']}, {state})")
    chosen = [a for a in agents if a["available"] and arguments.agent in (None, a["name"])]
    if not chosen:
        raise ProtocolError(f"no available agent{' named ' + arguments.agent if arguments.agent else ''}")
    agent_id = chosen[0]["id"]

    name, inputs, outputs = client.agent_info(agent_id)
    print(f"agent {agent_id} ({name}): {len(inputs)} inputs, {len(outputs)} outputs")
    input_names = [v["name"] for v in inputs]
    output_names = [v["name"] for v in outputs]
    try:
        angle_input = input_names.index(f"/{arguments.joint}/DesiredAngle")
        angle_output = output_names.index(f"/{arguments.joint}/JointAngle")
    except ValueError:
        raise ProtocolError(f"agent {name} has no joint {arguments.joint}") from None

    if not client.take_control(agent_id):
        raise ProtocolError(f"agent {agent_id} refused control")
    print(f"controlling agent {agent_id}; moving {arguments.joint} (input {angle_input}, output {angle_output})")

    path = f"/Sim/{name}/{arguments.joint}/JointAngle"
    value_id = client.value_ids(path).get(path)  # a regular expression matching the whole path
    if value_id is None or client.observe([value_id]) != [value_id]:
        raise ProtocolError(f"cannot observe {path}")
    print(f"observing {path} (value id {value_id})")

    # Every input at its reset value (angle 0, default torque), the chosen joint on a sine at full torque.
    # Inputs are normalised: angles −1…1 ↔ ±150°, torques 0…1.
    step_inputs = [0.0 if "Angle" in n else DEFAULT_TORQUE for n in input_names]
    step_inputs[angle_input + 1] = 1.0
    low, high, largest_gap = math.inf, -math.inf, 0.0
    period = max(arguments.steps / 2, 1)
    for step in range(arguments.steps):
        desired = arguments.amplitude * math.sin(2 * math.pi * step / period)
        step_inputs[angle_input] = desired / ANGLE_RANGE_DEGREES
        outputs, _ = client.step(agent_id, step_inputs)
        measured = outputs[angle_output]  # outputs are raw: degrees
        observed = float(client.get(value_id))  # the same value, read by id as text
        largest_gap = max(largest_gap, abs(observed - measured))
        low, high = min(low, measured), max(high, measured)
        if step % 20 == 0 or step == arguments.steps - 1:
            print(f"step {step:3d}: desired {desired:7.2f} deg, JointAngle output {measured:7.2f} deg, "
                  f"observed value {observed:7.2f}")
    print(f"steps: {arguments.steps}")
    print(f"{arguments.joint} JointAngle ranged from {low:.2f} to {high:.2f} deg (commanded ±{arguments.amplitude:g})")
    print(f"largest difference between the step output and the observed value: {largest_gap:.6f} deg")

    client.reset(arguments.seed)
    print(f"reset with seed {arguments.seed}: {path} = {float(client.get(value_id)):.2f} deg")
    client.close()
    print("session ended")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=45454)
    parser.add_argument("--agent", help="agent name (default: the first available)")
    parser.add_argument("--joint", default="Right/ShoulderYaw", help="motor to move, e.g. Right/Knee")
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--amplitude", type=float, default=30.0, help="degrees")
    parser.add_argument("--seed", type=int, default=1)
    arguments = parser.parse_args()
    if not 0 < arguments.port < 65536 or arguments.steps < 1:
        parser.error("--port must be 1..65535 and --steps at least 1")
    try:
        run(arguments)
    except (ProtocolError, OSError, struct.error, ValueError, UnicodeDecodeError) as error:
        print(f"osp_example_client.py: {error}", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
