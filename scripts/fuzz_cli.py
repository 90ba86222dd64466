#!/usr/bin/env python3
"""A mutation fuzzer over the `radiosity` command-line tool.

Each case is one run of the built binary on a hostile input, under a time
limit and a memory limit (RLIMIT_AS), and its outcome is classified:

  ok       exit 0
  error    exit 1 with an `error:` message (a clean refusal)
  usage    exit 2 (clap refused the command line)
  panic    exit 101 or a `panicked` message
  timeout  still running at the time limit (killed)
  memory   killed or aborted for want of memory under the limit
  crash    any other signal or exit code

The cases come from these generators:

  json       JSON mutations of exported scenes: numbers replaced by hostile
             ones, keys deleted, values of another type, arrays emptied or
             repeated, indices swapped, URIs pointed elsewhere
  bytes      byte mutations of exported .glb and .gltf files: flips, runs,
             insertions, deletions, truncations
  scene      random valid scenes with hostile numbers: scales from micrometres
             to the coordinate bound, reflectances at 0 and 1, emission over
             600 orders of magnitude, slivers, node transforms of every kind
  options    the built-in Cornell box under hostile command-line values
  lights     KHR_lights_punctual lights of hostile values and types, placed
             inside, outside, at a surface, far away, thousands at one place
  textures   base-colour textures broken, cut short, oversized, named by
             hostile URIs, under hostile texture transforms
  probe      points files with byte-order marks, headers, typos, odd line ends
  compare    solve and reference tables with hostile values, other scenes,
             other areas, missing or renamed surfaces
  signals    SIGINT, SIGTERM or SIGKILL at a random moment of a solve (now and
             then during its commit) that replaces a previous set
  concurrent two solves into one folder at once

An exit-0 run is judged by invariants as well (scripts/fuzz_invariants.py):
finite outputs, energy balance or a warning, no all-black picture without
a warning nor an all-white one, the output set of one run, no temporaries
left, inputs unchanged; a broken invariant is a failure ("invariant").

The seed is printed first; the same seed and options give the same cases.
A panic, timeout, memory kill, crash or broken invariant makes the script
exit with status 1 (after the summary), and `--keep DIR` saves each such
case (its files and command line) for a regression test.

Usage: python3 scripts/fuzz_cli.py [--cases N] [--seed S] [--binary PATH]
"""

import argparse
import base64
import json
import math
import os
import random
import resource
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time

import fuzz_invariants as inv
import fuzz_more

# Settings that keep one solve well under a second on the seed scenes, and a
# small image.
QUICK = ["--hemicube-res", "16", "--max-depth", "1", "--initial-depth", "0",
         "--threads", "1", "--quiet"]
IMAGE = ["--width", "24", "--height", "16"]

# Numbers that have broken numerical code before: zeros of both signs,
# subnormals, the edges of f32 and f64, integers at the edges of u32, i64 and
# the f64 mantissa, and ordinary values of every sign and size.
HOSTILE_NUMBERS = [
    0, -0.0, 1, -1, 0.5, 2, 3, 7, 255, 65535, 4294967295, 4294967296,
    9007199254740993, -9223372036854775808, 18446744073709551615,
    1e-320, 5e-324, 1e-300, 1e-45, 1.4e-45, 1e-38, 1e-12, 1e-6,
    1e6, 1e12, 1e15, 1e16, 1e20, 3.4e38, 3.5e38, 1e300, 1.7976931348623157e308,
    -1e-320, -1e20, -3.5e38, 0.9999999, 1.0000001, 123456.789,
]
OTHER_VALUES = [None, True, False, "", "x", "data:,", [], {}, [0], {"a": 1}]
URIS = [
    "missing.bin", "../outside.bin", "/absolute.bin", "sub/../../up.bin",
    "file:///etc/passwd", "https://example.com/a.bin", "data:application/octet-stream;base64,",
    "data:application/octet-stream;base64,AAAA", "data:;base64,////", "%2e%2e/x", ".",
    "folder", "C:\\x.bin", "a" * 300,
]


class Tally:
    """Counts of outcomes per generator."""

    def __init__(self):
        self.counts = {}

    def add(self, generator, outcome):
        key = (generator, outcome)
        self.counts[key] = self.counts.get(key, 0) + 1

    def total(self, outcome):
        return sum(n for (_, o), n in self.counts.items() if o == outcome)

    def report(self):
        outcomes = ["ok", "error", "usage", "panic", "timeout", "memory", "crash", "invariant"]
        generators = sorted({g for g, _ in self.counts})
        lines = ["generator " + " ".join(f"{o:>8}" for o in outcomes)]
        for g in generators + ["all"]:
            cells = []
            for o in outcomes:
                n = self.total(o) if g == "all" else self.counts.get((g, o), 0)
                cells.append(f"{n:>8}")
            lines.append(f"{g:<9} " + " ".join(cells))
        return "\n".join(lines)


# ---------------------------------------------------------------------------
# Running one case
# ---------------------------------------------------------------------------

def limits(memory_bytes):
    """The child's limits, set between fork and exec."""
    def apply():
        resource.setrlimit(resource.RLIMIT_AS, (memory_bytes, memory_bytes))
        # No core files from aborts.
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        os.setsid()
    return apply


def run(binary, args, cwd, timeout, memory_bytes):
    """Runs the binary; returns (outcome, exit code, stderr text)."""
    child = subprocess.Popen(
        [binary] + args, cwd=cwd, stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        preexec_fn=limits(memory_bytes),
    )
    try:
        _, err = child.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(child.pid, signal.SIGKILL)
        child.communicate()
        return "timeout", None, ""
    text = err.decode("utf-8", "replace")
    return classify(child.returncode, text), child.returncode, text


def classify(code, text):
    """The outcome of an exit code and the error output."""
    if code == 101 or "panicked" in text:
        return "panic"
    if "memory allocation of" in text or code == -signal.SIGKILL:
        return "memory"
    if code == 0:
        return "ok"
    if code == 1 and "error:" in text:
        return "error"
    if code == 2:
        return "usage"
    return "crash"


# ---------------------------------------------------------------------------
# JSON mutations
# ---------------------------------------------------------------------------

def slots(value, path, out):
    """Every (path, value) in a JSON document, depth first."""
    out.append((path, value))
    if isinstance(value, dict):
        for k, v in value.items():
            slots(v, path + [k], out)
    elif isinstance(value, list):
        for i, v in enumerate(value):
            slots(v, path + [i], out)


def get_parent(doc, path):
    node = doc
    for key in path[:-1]:
        node = node[key]
    return node


def mutate_json(doc, rng):
    """Applies one to four random mutations to a glTF document in place."""
    for _ in range(rng.choice([1, 1, 2, 3, 4])):
        found = []
        slots(doc, [], found)
        found = [(p, v) for p, v in found if p]
        if not found:
            return
        numbers = [(p, v) for p, v in found if isinstance(v, (int, float)) and not isinstance(v, bool)]
        kind = rng.random()
        # Values rather than indices, mostly: the importer then reaches the
        # geometry, materials and cameras with hostile numbers.
        values = [(p, v) for p, v in numbers
                  if any(k in p for k in ("materials", "nodes", "cameras", "extensions"))]
        if kind < 0.45 and numbers:
            path, _ = rng.choice(values if values and rng.random() < 0.7 else numbers)
            get_parent(doc, path)[path[-1]] = rng.choice(HOSTILE_NUMBERS)
        elif kind < 0.55:
            path, _ = rng.choice(found)
            parent = get_parent(doc, path)
            if isinstance(parent, dict):
                del parent[path[-1]]
            elif parent:
                parent.pop(path[-1])
        elif kind < 0.65:
            path, _ = rng.choice(found)
            get_parent(doc, path)[path[-1]] = rng.choice(OTHER_VALUES)
        elif kind < 0.75:
            arrays = [(p, v) for p, v in found if isinstance(v, list) and v]
            if arrays:
                path, array = rng.choice(arrays)
                how = rng.random()
                if how < 0.3:
                    array.clear()
                elif how < 0.7:
                    array.extend([rng.choice(array)] * rng.randint(1, 50))
                else:
                    rng.shuffle(array)
        elif kind < 0.85 and len(numbers) > 1:
            (a, va), (b, vb) = rng.sample(numbers, 2)
            get_parent(doc, a)[a[-1]] = vb
            get_parent(doc, b)[b[-1]] = va
        elif kind < 0.92:
            uris = [(p, v) for p, v in found if p[-1] == "uri"]
            if uris:
                path, _ = rng.choice(uris)
                get_parent(doc, path)[path[-1]] = rng.choice(URIS)
        else:
            # Structure a well-formed file rarely has: a cycle, a deep chain, a
            # matrix of hostile numbers, an index far out of range.
            nodes = doc.setdefault("nodes", []) if isinstance(doc, dict) else []
            if isinstance(nodes, list) and nodes and isinstance(nodes[0], dict):
                how = rng.random()
                if how < 0.3:
                    nodes[0]["children"] = [0]
                elif how < 0.6:
                    nodes[0]["matrix"] = [rng.choice(HOSTILE_NUMBERS) for _ in range(16)]
                else:
                    nodes[0]["mesh"] = rng.choice([10**6, 2**32, -1])


def dumps(doc, rng):
    """The document as text, now and then with NaN or Infinity (not JSON)."""
    text = json.dumps(doc)
    if rng.random() < 0.05:
        text = text.replace("0.0", "NaN", 1)
    if rng.random() < 0.05:
        text = text.replace("1.0", "Infinity", 1)
    return text


# ---------------------------------------------------------------------------
# Byte mutations
# ---------------------------------------------------------------------------

def mutate_payload(ext, data, rng):
    """Mutates the binary buffer only (the GLB BIN chunk, or the base64 data
    URI of a .gltf), so that the file still parses and the importer reaches
    the geometry with broken positions and indices."""
    if ext == "glb":
        json_len = struct.unpack_from("<I", data, 12)[0]
        bin_start = 20 + json_len + 8
        if bin_start >= len(data):
            return mutate_bytes(data, rng)
        return data[:bin_start] + mutate_raw(data[bin_start:], rng)
    doc = json.loads(data)
    prefix, payload = doc["buffers"][0]["uri"].split(",", 1)
    raw = mutate_raw(base64.b64decode(payload), rng)
    doc["buffers"][0]["uri"] = prefix + "," + base64.b64encode(raw).decode()
    return json.dumps(doc).encode()


# Four-byte values that break numbers and indices: all ones, quiet NaN,
# infinity, the largest f32, one, zero.
NASTY_WORDS = [b"\xff\xff\xff\xff", b"\x00\x00\xc0\x7f", b"\x00\x00\x80\x7f",
               b"\xff\xff\x7f\x7f", b"\x01\x00\x00\x00", b"\x00\x00\x00\x00"]


def mutate_raw(raw, rng):
    """Bit flips and nasty words in a buffer, keeping its length."""
    body = bytearray(raw)
    for _ in range(rng.randint(1, 8)):
        at = rng.randrange(len(body))
        if rng.random() < 0.5:
            body[at] ^= 1 << rng.randrange(8)
        else:
            body[at:at + 4] = rng.choice(NASTY_WORDS)
    return bytes(body[:len(raw)])


def split_glb(data):
    """The JSON and BIN chunks of a well-formed GLB file."""
    json_len = struct.unpack_from("<I", data, 12)[0]
    text = data[20:20 + json_len]
    rest = data[20 + json_len:]
    binary = rest[8:8 + struct.unpack_from("<I", rest, 0)[0]] if len(rest) >= 8 else b""
    return text, binary


def glb(text, binary):
    """A GLB file of a JSON chunk and a BIN chunk, each padded to 4 bytes."""
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    body = struct.pack("<I4s", len(text), b"JSON") + text
    if binary:
        body += struct.pack("<I4s", len(binary), b"BIN\0") + binary
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def mutate_bytes(data, rng):
    data = bytearray(data)
    for _ in range(rng.randint(1, 8)):
        if not data:
            break
        kind = rng.random()
        at = rng.randrange(len(data))
        if kind < 0.4:
            data[at] ^= 1 << rng.randrange(8)
        elif kind < 0.6:
            data[at:at + rng.randint(1, 16)] = bytes([rng.choice([0, 0xFF, 0x7F, 0x80])]) * rng.randint(1, 16)
        elif kind < 0.75:
            data[at:at] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 32)))
        elif kind < 0.9:
            del data[at:at + rng.randint(1, 64)]
        else:
            del data[at:]
    return bytes(data)


# ---------------------------------------------------------------------------
# Random valid scenes with hostile numbers
# ---------------------------------------------------------------------------

class SceneWriter:
    """A glTF document of triangle meshes in one embedded buffer."""

    def __init__(self):
        self.bin = bytearray()
        self.doc = {"asset": {"version": "2.0"}, "accessors": [], "bufferViews": [],
                    "meshes": [], "nodes": [], "materials": [],
                    "extensionsUsed": ["KHR_materials_emissive_strength"]}

    def material(self, reflectance, radiance, strength):
        m = {"pbrMetallicRoughness": {"baseColorFactor": reflectance + [1.0]},
             "emissiveFactor": radiance}
        if strength is not None:
            m["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": strength}}
        self.doc["materials"].append(m)
        return len(self.doc["materials"]) - 1

    def mesh(self, points, material):
        while len(self.bin) % 4:
            self.bin.append(0)
        offset = len(self.bin)
        for p in points:
            self.bin += struct.pack("<3f", *p)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": offset, "byteLength": 12 * len(points)})
        lo = [min(p[k] for p in points) for k in range(3)]
        hi = [max(p[k] for p in points) for k in range(3)]
        self.doc["accessors"].append({"bufferView": len(self.doc["bufferViews"]) - 1,
                                      "componentType": 5126, "count": len(points),
                                      "type": "VEC3", "min": lo, "max": hi})
        self.doc["meshes"].append({"primitives": [{"attributes": {"POSITION": len(self.doc["accessors"]) - 1},
                                                   "material": material}]})
        return len(self.doc["meshes"]) - 1

    def node(self, node):
        self.doc["nodes"].append(node)

    def finish(self):
        self.doc["buffers"] = [{"byteLength": len(self.bin),
                                "uri": "data:application/octet-stream;base64," + base64.b64encode(self.bin).decode()}]
        self.doc["scenes"] = [{"nodes": list(range(len(self.doc["nodes"])))}]
        self.doc["scene"] = 0
        return self.doc


def f32(x):
    """x rounded to single precision, or as large as f32 goes."""
    try:
        return struct.unpack("<f", struct.pack("<f", x))[0]
    except OverflowError:
        return math.copysign(3.4e38, x)


def quad(a, b, c, d):
    return [a, b, c, a, c, d]


def random_scene(rng):
    """A closed box with lights and blocks, at a hostile scale, with hostile
    materials and node transforms."""
    w = SceneWriter()
    scale = rng.choice([1e-6, 1e-3, 1.0, 1.0, 1.0, 1e3, 1e6, 1e12, 1e14])
    # A reflectance of 1 in a closed box is refused (the system is singular),
    # so it is rare; an emissive strength beyond f32 is refused by the parser.
    def rho():
        if rng.random() < 0.03:
            return [1.0, 1.0, 1.0]
        return [rng.choice([0.0, 1e-9, 0.2, 0.5, 0.8, 0.99, 0.999]) for _ in range(3)]
    wall = w.material(rho(), [0.0, 0.0, 0.0], None)
    strength = rng.choice([None, 1e-30, 1e-20, 1e-5, 1.0, 1e3, 1e20, 1e30, 1e100])
    light = w.material(rho(), [rng.choice([0.0, 1e-30, 0.5, 1.0]) for _ in range(3)], strength)
    s = lambda x, y, z: [f32(x * scale), f32(y * scale), f32(z * scale)]
    faces = [
        quad(s(0, 0, 0), s(0, 0, 1), s(1, 0, 1), s(1, 0, 0)),   # floor, up
        quad(s(0, 1, 0), s(1, 1, 0), s(1, 1, 1), s(0, 1, 1)),   # ceiling, down
        quad(s(0, 0, 0), s(1, 0, 0), s(1, 1, 0), s(0, 1, 0)),   # z = 0
        quad(s(0, 0, 1), s(0, 1, 1), s(1, 1, 1), s(1, 0, 1)),   # z = 1
        quad(s(0, 0, 0), s(0, 1, 0), s(0, 1, 1), s(0, 0, 1)),   # x = 0
        quad(s(1, 0, 0), s(1, 0, 1), s(1, 1, 1), s(1, 1, 0)),   # x = 1
    ]
    for f in faces:
        w.node({"mesh": w.mesh(f, wall)})
    size = rng.choice([0.5, 0.1, 1e-3, 1e-6])
    x0 = 0.5 - size / 2
    lamp = quad(s(x0, 0.999, x0), s(x0 + size, 0.999, x0), s(x0 + size, 0.999, x0 + size), s(x0, 0.999, x0 + size))
    w.node({"mesh": w.mesh(lamp, light)})
    for _ in range(rng.randint(0, 6)):
        kind = rng.random()
        x, z = rng.uniform(0.1, 0.8), rng.uniform(0.1, 0.8)
        h = rng.choice([0.1, 0.3, 1e-7])
        if kind < 0.5:
            # A sliver or an ordinary triangle standing on the floor.
            thin = rng.choice([0.1, 1e-4, 1e-9])
            tri = [s(x, 0.01, z), s(x + 0.1, 0.01, z), s(x + 0.05, 0.01 + h, z + thin)]
            w.node({"mesh": w.mesh(tri, rng.choice([wall, light]))})
        else:
            node = {"mesh": w.mesh(quad(s(0, 0, 0), s(0.1, 0, 0), s(0.1, h, 0), s(0, h, 0)), wall)}
            how = rng.random()
            if how < 0.3:
                node["translation"] = [x * scale, 0.01 * scale, z * scale]
                node["rotation"] = [rng.uniform(-1, 1) for _ in range(4)]
            elif how < 0.6:
                node["scale"] = [rng.choice([1.0, -1.0, 0.0, 1e-12, 1e12]) for _ in range(3)]
            else:
                m = [1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0, 0, x * scale, 0.01 * scale, z * scale, 1.0]
                # Mostly a hostile scale or shear in the upper 3 x 3, now and
                # then anywhere (the bottom row makes it projective).
                k = rng.choice([0, 1, 2, 4, 5, 6, 8, 9, 10] * 4 + list(range(16)))
                m[k] = rng.choice(HOSTILE_NUMBERS)
                node["matrix"] = m
            w.node(node)
    return w.finish()


# ---------------------------------------------------------------------------
# Hostile command-line values
# ---------------------------------------------------------------------------

OPTIONS = {
    "--width": ["0", "1", "16385", "4294967296", "-1", "x"],
    "--height": ["0", "1", "100000"],
    "--threads": ["0", "1", "1025", "100000", "18446744073709551616"],
    "--time-budget": ["1e20", "NaN", "-1", "inf", "0", "1e-300"],
    "--hemicube-res": ["0", "7", "8", "4097", "100000"],
    "--patch-size": ["0", "-1", "1e-300", "1e300", "NaN", "inf"],
    "--tolerance": ["0", "1e-300", "1", "NaN", "-1"],
    "--refine-tolerance": ["0", "-1", "NaN", "1e300"],
    "--max-depth": ["0", "255"],
    "--initial-depth": ["0", "255"],
    "--uniform-depth": ["0", "12", "255"],
    "--min-element-area": ["0", "-1", "1e-300", "NaN"],
    "--max-elements": ["0", "1", "18446744073709551615"],
    "--source-tolerance": ["-1", "NaN", "1e-300"],
    "--emitter-samples": ["element", "rays", ""],
    "--bounces": ["0", "1", "4294967295"],
    "--exposure": ["NaN", "1e300", "-1e300"],
    "--camera": ["0,0,0,0,0,0,60", "0,0,0,1,1,1,0", "0,0,0,1,1,1,180", "nan,0,0,1,1,1,60", "1e300,0,0,0,0,0,60"],
    "--false-colour-range": ["0,0", "1,0", "1e-300,1e300"],
    "--unshot-tolerance": ["0", "1", "NaN"],
    "--max-shots": ["0", "1"],
    "--preview-every": ["0", "1"],
    "--seed": ["0", "18446744073709551615"],
}


def hostile_options(rng):
    """Base options with one to three of them replaced by hostile values."""
    chosen = {}
    for _ in range(rng.randint(1, 3)):
        name = rng.choice(sorted(OPTIONS))
        chosen[name] = rng.choice(OPTIONS[name])
    base = [a for a in QUICK + IMAGE if a != "--quiet"]
    args = ["--quiet"]
    for k in range(0, len(base), 2):
        if base[k] not in chosen:
            args += base[k:k + 2]
    args += [f"{name}={value}" for name, value in chosen.items()]
    if rng.random() < 0.3:
        args += ["--solver", "progressive"]
    if rng.random() < 0.3 or "--false-colour-range" in chosen:
        args += ["--false-colour"]
    return args


# ---------------------------------------------------------------------------
# The cases
# ---------------------------------------------------------------------------

def seeds(binary, folder):
    """Scenes exported by the binary itself, as .gltf and .glb."""
    out = []
    for name in ["cornell_box", "penumbra_parallel"]:
        for ext in ["gltf", "glb"]:
            path = os.path.join(folder, f"{name}.{ext}")
            subprocess.run([binary, "export-scene", name, "-o", path], check=True,
                           stdout=subprocess.DEVNULL)
            with open(path, "rb") as f:
                out.append((ext, f.read()))
    return out


def command_for(rng, scene, case_dir):
    """A subcommand that reads `scene`: mostly solve, sometimes bake then
    render, probe or reference; now and then with an output named after the
    scene itself (which must be refused)."""
    kind = rng.random()
    if kind < 0.04:
        return [rng.choice([["solve", scene, "--out", "out", "--mesh-out", scene] + QUICK + IMAGE,
                            ["reference", scene, "--paths", "20", "-o", scene]])]
    if kind < 0.7:
        return [["solve", scene, "--out", "out"] + QUICK + IMAGE]
    if kind < 0.85:
        return [["bake", scene, "-o", "baked.glb"] + QUICK,
                ["render", "baked.glb", "--out", "rendered", "--quiet"] + IMAGE]
    if kind < 0.95:
        with open(os.path.join(case_dir, "points.csv"), "w") as f:
            f.write("0.3,0,0.3,0,1,0\n0.5,0.5,0.5,0,-1,0\n")
        return [["probe", scene, "--points", "points.csv", "-o", "probe.csv"] + QUICK]
    return [["reference", scene, "--paths", "200", "--threads", "1", "-o", "ref.json"]]


def make_case(rng, generator, seed_files, case_dir):
    """Writes the case's input into `case_dir`; returns the commands to run."""
    if generator == "options":
        return [["solve", "cornell_box", "--out", "out"] + hostile_options(rng)]
    if generator == "scene":
        doc = random_scene(rng)
        name = "scene.gltf"
        with open(os.path.join(case_dir, name), "w") as f:
            f.write(json.dumps(doc))
    else:
        ext, data = rng.choice(seed_files)
        name = f"scene.{ext}"
        if generator == "json" and ext == "gltf":
            doc = json.loads(data)
            mutate_json(doc, rng)
            data = dumps(doc, rng).encode()
        elif generator == "json":
            text, binary = split_glb(data)
            doc = json.loads(text)
            mutate_json(doc, rng)
            data = glb(dumps(doc, rng).encode(), binary)
        elif rng.random() < 0.6:
            data = mutate_payload(ext, data, rng)
        else:
            data = mutate_bytes(data, rng)
        with open(os.path.join(case_dir, name), "wb") as f:
            f.write(data)
    os.makedirs(os.path.join(case_dir, "folder"), exist_ok=True)
    return command_for(rng, name, case_dir)


FAILURES = {"panic", "timeout", "memory", "crash", "invariant"}

OUTPUT_FOLDERS = ("out", "rendered", "folder")


def judge(commands, case_dir, err):
    """The invariants an exit-0 run of the older generators' commands must
    hold (see fuzz_invariants)."""
    failures = []
    for command in commands:
        exposure = any(a.startswith("--exposure") for a in command)
        if command[0] == "solve":
            width = None if any(a.startswith("--width=") for a in command) else 24
            out = os.path.join(case_dir, "out")
            failures += fuzz_more.judge_solve(out, err, width, exposure)
        elif command[0] == "render":
            rendered = os.path.join(case_dir, "rendered")
            failures += inv.check_pictures(rendered, err, exposure) + inv.check_tidy(rendered)
        elif command[0] == "reference":
            try:
                with open(os.path.join(case_dir, "ref.json")) as f:
                    bad = inv.non_finite(json.load(f))
            except (OSError, ValueError) as e:
                bad = [str(e)]
            failures += [f"reference: non-finite or unreadable {bad[:3]}"] if bad else []
    return failures


def compare_tables(binary, work):
    """A solve's stats and a reference of the same scene, for `compare`."""
    subprocess.run([binary, "solve", "cornell_box", "--out", "tables"] + QUICK + IMAGE,
                   cwd=work, check=True)
    subprocess.run([binary, "reference", "cornell_box", "--paths", "200", "--threads", "1",
                    "-o", "tables/reference.json"], cwd=work, check=True)
    with open(os.path.join(work, "tables", "cornell_box.json")) as f:
        solution = json.load(f)
    with open(os.path.join(work, "tables", "reference.json")) as f:
        reference = json.load(f)
    return solution, reference


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--binary", default="target/release/radiosity")
    parser.add_argument("--cases", type=int, default=200)
    parser.add_argument("--seed", type=int, default=None, help="default: random, printed")
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds per command")
    parser.add_argument("--memory-mb", type=int, default=4096, help="address space per command")
    parser.add_argument("--generators", default="json,bytes,scene,options,lights,textures,"
                        "probe,compare,signals,concurrent")
    parser.add_argument("--keep", default=None, help="folder for the failing cases")
    parser.add_argument("--verbose", action="store_true", help="one line per case")
    args = parser.parse_args()

    seed = args.seed if args.seed is not None else random.SystemRandom().randrange(2**32)
    print(f"fuzz_cli: seed {seed} ({args.cases} cases; rerun with --seed {seed})", flush=True)
    binary = os.path.abspath(args.binary)
    if not os.access(binary, os.X_OK):
        sys.exit(f"fuzz_cli: no binary at {binary} (cargo build --release first)")
    generators = args.generators.split(",")
    rng = random.Random(seed)
    tally = Tally()
    failures = []
    memory = args.memory_mb << 20
    started = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="fuzz_cli_") as work:
        seed_files = seeds(binary, work)
        fuzz_more.CLASSIFY = classify
        tables = compare_tables(binary, work) if "compare" in generators else None
        for i in range(args.cases):
            generator = generators[i % len(generators)]
            case_rng = random.Random(rng.randrange(2**63))
            case_dir = os.path.join(work, f"case{i}")
            os.makedirs(case_dir)
            if generator == "compare":
                r = fuzz_more.case_compare(case_rng, run, binary, case_dir, tables,
                                           args.timeout, memory)
                outcome, last, broken = r.outcome, (r.command, r.code, r.err), r.failures
            elif generator in fuzz_more.GENERATORS:
                r = fuzz_more.GENERATORS[generator](case_rng, run, binary, case_dir, seed_files,
                                                    args.timeout, memory)
                outcome, last, broken = r.outcome, (r.command, r.code, r.err), r.failures
            else:
                commands = make_case(case_rng, generator, seed_files, case_dir)
                before = inv.digest_files(case_dir, skip=OUTPUT_FOLDERS)
                outcome, last = "ok", None
                for command in commands:
                    outcome, code, err = run(binary, command, case_dir, args.timeout, memory)
                    last = (command, code, err)
                    if outcome != "ok":
                        break
                broken = inv.check_inputs(before, case_dir, skip=OUTPUT_FOLDERS)
                if outcome == "ok":
                    broken += judge(commands, case_dir, last[2])
            if broken and outcome not in FAILURES:
                outcome = "invariant"
                last = (last[0], last[1], "\n".join(broken) + "\n" + (last[2] or ""))
            tally.add(generator, outcome)
            if args.verbose:
                why = last[2].strip().splitlines()[-1:] if last[2] else []
                print(f"case {i} {generator}: {outcome} {' '.join(last[0])} {' '.join(why)}"[:400],
                      flush=True)
            if outcome in FAILURES:
                command, code, err = last
                message = err.strip().splitlines()[:3]
                failures.append((i, generator, outcome, command, code, message))
                print(f"case {i} ({generator}): {outcome.upper()} exit {code}: radiosity "
                      f"{' '.join(command)}\n    " + "\n    ".join(message), flush=True)
                if args.keep:
                    target = os.path.join(args.keep, f"seed{seed}_case{i}_{outcome}")
                    shutil.copytree(case_dir, target, dirs_exist_ok=True)
                    with open(os.path.join(target, "command.txt"), "w") as f:
                        f.write("radiosity " + " ".join(command) + "\n")
            shutil.rmtree(case_dir, ignore_errors=True)
    print(tally.report())
    print(f"fuzz_cli: seed {seed}, {args.cases} cases in {time.monotonic() - started:.1f} s, "
          f"{len(failures)} failures")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
