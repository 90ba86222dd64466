"""The fuzzer's generators added for issue 48: mutations of punctual
lights, textures, probe points and compare inputs, signals sent to a run,
and two runs into one folder. Each case writes its inputs into its folder,
runs the binary (`run` from fuzz_cli) and returns what happened and which
invariants (fuzz_invariants) failed.
"""

import base64
import json
import os
import random
import signal
import struct
import subprocess
import time
import zlib

import fuzz_invariants as inv

# The outcome classifier, set by fuzz_cli.
CLASSIFY = None

QUICK = ["--hemicube-res", "16", "--max-depth", "1", "--initial-depth", "0",
         "--threads", "1", "--quiet"]

HOSTILE = [0, -0.0, -1, 1e-320, 5e-324, 1e-310, 2.3e-308, 1e-300, 1e-45, 1, 1000,
           3.4e38, 3.5e38, 1e300, 1.7976931348623157e308, "1000", "red", None, True,
           [], [1, 2], {"a": 1}, "", 1e20]


class Result:
    """What a case did: its outcome class, last command, exit code, standard
    error and the invariants that failed."""

    def __init__(self, outcome, command, code, err, failures=()):
        self.outcome, self.command, self.code, self.err = outcome, command, code, err
        self.failures = list(failures)


# ---------------------------------------------------------------------------
# Scenes with lights and textures

def room_doc(seed_files):
    """The exported Cornell box (.gltf) as a document."""
    data = next(d for ext, d in seed_files if ext == "gltf")
    return json.loads(data)


def random_light(rng):
    """A light, valid half the time (with intensities over the whole range a
    double holds), else with hostile values or types."""
    if rng.random() < 0.5:
        light = {"type": rng.choice(["point", "spot", "directional"]),
                 "intensity": rng.choice([1, 10, 1000, 1e-300, 1e-30, 1e30, 3.4e38])}
        if rng.random() < 0.3:
            light["color"] = [rng.choice([0, 0.2, 1]) for _ in range(3)]
        if rng.random() < 0.3:
            light["range"] = rng.choice([0.01, 0.3, 100])
        return light
    light = {"type": rng.choice(["point", "spot", "directional", "point", "area", 7, None])}
    for field in ["intensity", "color", "range"]:
        roll = rng.random()
        if roll < 0.4:
            continue
        if field == "color" and roll < 0.8:
            light[field] = [rng.choice([0, 0.5, 1, 1e-310, 2, 1e300]) for _ in range(3)]
        else:
            light[field] = rng.choice(HOSTILE)
    if light["type"] == "spot" and rng.random() < 0.7:
        light["spot"] = {k: rng.choice(HOSTILE + [0.1, 0.5, 1.5])
                         for k in ["innerConeAngle", "outerConeAngle"] if rng.random() < 0.6}
    if light["type"] is None:
        del light["type"]
    return light


def add_lights(doc, rng):
    """One to four lights placed by new nodes: in the box, outside it, shut
    in a closed crate, or many at one place."""
    lights = [random_light(rng) for _ in range(rng.randint(1, 4))]
    doc.setdefault("extensionsUsed", []).append("KHR_lights_punctual")
    doc.setdefault("extensions", {})["KHR_lights_punctual"] = {"lights": lights}
    nodes = doc.setdefault("nodes", [])
    scene_nodes = doc["scenes"][0]["nodes"]
    for i in range(len(lights)):
        where = rng.choice([[0.28, 0.27, 0.28], [0.28, 0.5, -2.0], [0.28, 0.0, 0.28],
                            [1e6, 0, 0], [0.28, 0.548, 0.28]])
        node = {"translation": where, "extensions": {"KHR_lights_punctual": {"light": i}}}
        if rng.random() < 0.3:
            node["rotation"] = [rng.uniform(-1, 1) for _ in range(4)]
        copies = rng.choice([1, 1, 1, 50, 2000])
        for _ in range(copies):
            nodes.append(dict(node))
            scene_nodes.append(len(nodes) - 1)
    if rng.random() < 0.5:
        # Without the emitting material, the lights alone light the box.
        for m in doc.get("materials", []):
            m.pop("emissiveFactor", None)
            m.pop("extensions", None)


def png_bytes(width, height, rng):
    rows = b"".join(b"\0" + bytes(rng.randrange(256) for _ in range(3 * width)) for _ in range(height))
    chunk = lambda kind, body: struct.pack(">I", len(body)) + kind + body + \
        struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def add_texture(doc, rng, case_dir):
    """A base-colour texture on one material: a small PNG, now and then
    broken (bits flipped, cut short, a huge declared size) or named by a
    hostile URI, with a hostile texture transform."""
    image = png_bytes(rng.choice([1, 2, 8]), rng.choice([1, 3, 8]), rng)
    how = rng.random()
    if how < 0.2:
        image = image[:rng.randrange(8, len(image))]
    elif how < 0.4:
        image = bytearray(image)
        image[rng.randrange(8, len(image))] ^= 1 << rng.randrange(8)
        image = bytes(image)
    elif how < 0.5:
        image = image[:16] + struct.pack(">II", 1 << 30, 1 << 30) + image[24:]
    if rng.random() < 0.5:
        uri = "data:image/png;base64," + base64.b64encode(image).decode()
    else:
        with open(os.path.join(case_dir, "tex.png"), "wb") as f:
            f.write(image)
        uri = rng.choice(["tex.png", "tex.png", "missing.png", "../tex.png", "tex.png?x"])
    doc["images"] = [{"uri": uri}]
    doc["samplers"] = [{}]
    doc["textures"] = [{"source": 5 if rng.random() < 0.1 else 0, "sampler": 0}]
    material = rng.choice(doc["materials"])
    info = {"index": 0}
    if rng.random() < 0.4:
        info["extensions"] = {"KHR_texture_transform": {
            "scale": [rng.choice(HOSTILE[:12]), 1], "offset": [0, rng.choice(HOSTILE[:12])]}}
        doc.setdefault("extensionsUsed", []).append("KHR_texture_transform")
    material.setdefault("pbrMetallicRoughness", {})["baseColorTexture"] = info


def solve_case(rng, run, binary, case_dir, doc, timeout, memory):
    with open(os.path.join(case_dir, "scene.gltf"), "w") as f:
        f.write(json.dumps(doc))
    width = 24
    command = ["solve", "scene.gltf", "--out", "out", "--width", str(width), "--height", "16"] + QUICK
    if rng.random() < 0.3:
        command += ["--solver", "progressive"]
    before = inv.digest_files(case_dir, skip=("out",))
    outcome, code, err = run(binary, command, case_dir, timeout, memory)
    failures = inv.check_inputs(before, case_dir, skip=("out",))
    if outcome == "ok":
        failures += judge_solve(os.path.join(case_dir, "out"), err, width, exposure_given=False)
    return Result(outcome, command, code, err, failures)


def judge_solve(out, err, width, exposure_given):
    failures = []
    for name in sorted(os.listdir(out)):
        if name.endswith(".json") and not name.startswith("."):
            failures += inv.check_stats(os.path.join(out, name), err)
    return failures + inv.check_pictures(out, err, exposure_given) + \
        inv.check_set(out, width) + inv.check_tidy(out)


def case_lights(rng, run, binary, case_dir, seed_files, timeout, memory):
    doc = room_doc(seed_files)
    add_lights(doc, rng)
    return solve_case(rng, run, binary, case_dir, doc, timeout, memory)


def case_textures(rng, run, binary, case_dir, seed_files, timeout, memory):
    doc = room_doc(seed_files)
    add_texture(doc, rng, case_dir)
    return solve_case(rng, run, binary, case_dir, doc, timeout, memory)


# ---------------------------------------------------------------------------
# Probe points and compare inputs

POINTS = ["0.3,0,0.3,0,1,0", "0.5,0.5,0.5,0,-1,0", "0.1,0.2,0.0,0,0,1"]


def case_probe(rng, run, binary, case_dir, seed_files, timeout, memory):
    lines = [rng.choice(POINTS) for _ in range(rng.randint(0, 6))]
    if rng.random() < 0.4:
        lines.insert(0, rng.choice(["x,y,z,nx,ny,nz", "X;Y;Z", "# points", "x,y,z"]))
    for _ in range(rng.randint(0, 2)):
        if lines:
            k = rng.randrange(len(lines))
            lines[k] = rng.choice([lines[k] + "x", lines[k].replace(",", ";"), lines[k] + ",7",
                                   "nan,0,0,0,1,0", "1e400,0,0,0,1,0", "", "  ", lines[k] + "\r"])
    text = "\n".join(lines) + rng.choice(["\n", "", "\r\n"])
    if rng.random() < 0.4:
        text = "\ufeff" + text
    with open(os.path.join(case_dir, "points.csv"), "w", encoding="utf-8", newline="") as f:
        f.write(text)
    output = "points.csv" if rng.random() < 0.1 else "probe.csv"
    command = ["probe", "cornell_box", "--points", "points.csv", "-o", output] + QUICK
    before = inv.digest_files(case_dir)
    outcome, code, err = run(binary, command, case_dir, timeout, memory)
    failures = inv.check_inputs(before, case_dir)
    if outcome == "ok":
        body = text.lstrip("\ufeff")
        given = [ln for ln in body.splitlines() if ln.strip()]
        numeric = [ln for ln in given if all(_is_number(x) for x in ln.split(","))]
        header = len(given) - len(numeric)
        with open(os.path.join(case_dir, output)) as f:
            rows = f.read().splitlines()[1:]
        if header > 1 or len(rows) != len(numeric):
            failures.append(f"probe: {len(numeric)} points given, {len(rows)} rows written")
        for row in rows:
            for field in row.split(",")[:12]:
                if field and not _is_finite(field):
                    failures.append(f"probe: non-finite field {field}")
    return Result(outcome, command, code, err, failures)


def _is_number(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


def _is_finite(text):
    try:
        return abs(float(text)) < float("inf")
    except ValueError:
        return False


def mutate_table(table, rng):
    surfaces = table["surfaces"]
    how = rng.random()
    s = rng.choice(surfaces)
    if how < 0.3:
        s["radiosity"][rng.randrange(3)] = rng.choice(HOSTILE)
    elif how < 0.45:
        table["scene"] = rng.choice(["other", "", None, 3])
    elif how < 0.6:
        s["area"] = rng.choice(HOSTILE[:14] + [s.get("area", 1) * 1.5])
    elif how < 0.75:
        s["name"] = rng.choice(["", "x", surfaces[0]["name"]])
    elif how < 0.85:
        surfaces.remove(s)
    else:
        s["std_error"] = rng.choice(HOSTILE)


def case_compare(rng, run, binary, case_dir, tables, timeout, memory):
    """`tables` holds a solve's stats and a reference of the same scene."""
    solution, reference = json.loads(json.dumps(tables[0])), json.loads(json.dumps(tables[1]))
    for _ in range(rng.randint(0, 2)):
        mutate_table(rng.choice([solution, reference]), rng)
    for name, table in [("solution.json", solution), ("reference.json", reference)]:
        with open(os.path.join(case_dir, name), "w") as f:
            f.write(json.dumps(table))
    command = ["compare", "solution.json", "reference.json"]
    child = subprocess.run([binary] + command, cwd=case_dir, capture_output=True, timeout=timeout)
    err = child.stderr.decode("utf-8", "replace")
    out = child.stdout.decode("utf-8", "replace")
    outcome = CLASSIFY(child.returncode, err)
    failures = []
    if outcome == "ok":
        if "inf" in out or "NaN" in out:
            failures.append("compare: a non-finite figure printed")
        if solution.get("scene") != reference.get("scene") and \
                None not in (solution.get("scene"), reference.get("scene")):
            failures.append("compare: a reference of another scene accepted")
    return Result(outcome, command, child.returncode, err, failures)


# ---------------------------------------------------------------------------
# Signals and two runs at once

def solve_command(width, seed):
    return ["solve", "cornell_box", "--out", "out", "--width", str(width), "--height", "16",
            "--seed", str(seed), "--patch-size", "0.3"] + QUICK


def whole_set(out):
    """(png width, exr width, seed) of the visible set, or a failure."""
    try:
        png = inv.png_size(os.path.join(out, "cornell_box.png"))[0]
        exr = inv.exr_width(os.path.join(out, "cornell_box.exr"))
        with open(os.path.join(out, "cornell_box.json")) as f:
            seed = json.load(f)["seed"]
    except (OSError, ValueError, KeyError) as e:
        return None, f"set unreadable: {e}"
    runs = {(40, 1), (32, 2)}
    if png != exr or (png, seed) not in runs:
        return None, f"mixed set: png {png}, exr {exr}, seed {seed}"
    return (png, seed), None


def case_signals(rng, run, binary, case_dir, seed_files, timeout, memory):
    first = solve_command(40, 1)
    outcome, code, err = run(binary, first, case_dir, timeout, memory)
    if outcome != "ok":
        return Result(outcome, first, code, err, [f"the first run failed: {err[-200:]}"])
    sig = rng.choice([signal.SIGINT, signal.SIGTERM, signal.SIGKILL])
    env = dict(os.environ)
    if rng.random() < 0.5:
        env["RADIOSITY_TEST_COMMIT_PAUSE"] = "0.02"
    command = solve_command(32, 2)
    child = subprocess.Popen([binary] + command, cwd=case_dir, env=env,
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    time.sleep(rng.uniform(0.0, 0.25))
    try:
        child.send_signal(sig)
    except ProcessLookupError:
        pass
    try:
        _, raw = child.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        child.kill()
        child.communicate()
        return Result("timeout", command, None, "")
    err = raw.decode("utf-8", "replace")
    code = child.returncode
    failures = []
    expected = {signal.SIGINT: 130, signal.SIGTERM: 143, signal.SIGKILL: -signal.SIGKILL}[sig]
    if code not in (0, expected, -sig):
        failures.append(f"exit {code} after {sig.name}")
    if code == expected and sig != signal.SIGKILL and "stopped by" not in err:
        failures.append(f"no message after {sig.name}")
    out = os.path.join(case_dir, "out")
    _, why = whole_set(out)
    failures += [why] if why else []
    if code != -signal.SIGKILL:
        failures += inv.check_tidy(out)
    # The next run tidies whatever a kill left.
    again = run(binary, first, case_dir, timeout, memory)
    if again[0] != "ok":
        failures.append(f"the run after the signal failed: {again[2][-200:]}")
    else:
        failures += inv.check_tidy(out)
    outcome = "ok" if code in (0, expected, -sig) else "crash"
    return Result(outcome, command + [f"<{sig.name}>"], code, err, failures)


def case_concurrent(rng, run, binary, case_dir, seed_files, timeout, memory):
    a = subprocess.Popen([binary] + solve_command(40, 1), cwd=case_dir,
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    time.sleep(rng.uniform(0.0, 0.05))
    b = subprocess.Popen([binary] + solve_command(32, 2), cwd=case_dir,
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    errs = [p.communicate(timeout=timeout)[1].decode("utf-8", "replace") for p in (a, b)]
    codes = [a.returncode, b.returncode]
    failures = []
    for code, err in zip(codes, errs):
        if code not in (0, 1) or (code == 1 and "another run" not in err):
            failures.append(f"exit {code}: {err.strip()[-200:]}")
    if 0 not in codes:
        failures.append("both runs refused")
    _, why = whole_set(os.path.join(case_dir, "out"))
    failures += [why] if why else []
    failures += inv.check_tidy(os.path.join(case_dir, "out"))
    return Result("ok", solve_command(32, 2) + ["<two at once>"], codes[1], errs[1], failures)


GENERATORS = {
    "lights": case_lights,
    "textures": case_textures,
    "probe": case_probe,
    "signals": case_signals,
    "concurrent": case_concurrent,
}
