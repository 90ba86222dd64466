"""Invariants that the fuzzer holds an exit-0 run of `radiosity` to (issue
48): an exit status alone does not show a silently wrong result.

  finite     every number of a stats JSON, reference or probe CSV is finite
  energy     a closed scene whose solution is not cut short balances its
             power within 1%, or the run says it does not (a warning)
  picture    a PNG that is all black comes with the warning that says why;
             none is all white unless an exposure was asked for
  set        the files of one solve are of one run (the PNG and EXR widths
             agree with the JSON's), and every file the JSON lists exists
  tidy       no temporary or lock file is left beside the outputs
  inputs     no input file changed

Each check returns a list of failures in words (empty when it holds).
"""

import hashlib
import json
import math
import os
import struct
import zlib


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    return struct.unpack(">II", head[16:24])


def png_extremes(path):
    """The smallest and largest sample of an 8-bit RGB(A) PNG, not
    interlaced (what the tool writes), or None for another kind."""
    with open(path, "rb") as f:
        data = f.read()
    at, idat, header = 8, b"", None
    while at + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        at += 12 + length
    if header is None:
        return None
    width, height, depth, colour, _, _, interlace = header
    channels = {2: 3, 6: 4}.get(colour)
    if depth != 8 or channels is None or interlace:
        return None
    raw = zlib.decompress(idat)
    stride = width * channels
    previous = bytearray(stride)
    lo, hi = 255, 0
    for y in range(height):
        start = y * (stride + 1)
        kind, line = raw[start], bytearray(raw[start + 1:start + 1 + stride])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b = previous[i]
            c = previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pred) & 255
        colour_samples = [line[i] for i in range(stride) if channels == 3 or i % 4 != 3]
        lo, hi = min(lo, min(colour_samples)), max(hi, max(colour_samples))
        previous = line
    return lo, hi


def exr_width(path):
    with open(path, "rb") as f:
        data = f.read(4096)
    key = b"dataWindow\0box2i\0"
    at = data.find(key)
    if at < 0:
        return None
    x0, _, x1, _ = struct.unpack("<4i", data[at + len(key) + 4:at + len(key) + 20])
    return x1 - x0 + 1


def non_finite(value, where="", found=None):
    """Paths of the numbers in a parsed JSON value that are not finite."""
    found = [] if found is None else found
    if isinstance(value, float) and not math.isfinite(value):
        found.append(where)
    elif isinstance(value, dict):
        for k, v in value.items():
            non_finite(v, f"{where}.{k}", found)
    elif isinstance(value, list):
        for i, v in enumerate(value):
            non_finite(v, f"{where}[{i}]", found)
    return found


def check_stats(path, stderr):
    failures = []
    try:
        with open(path) as f:
            stats = json.load(f)
    except (OSError, ValueError) as e:
        return [f"{path}: unreadable stats ({e})"]
    bad = non_finite(stats)
    if bad:
        failures.append(f"{os.path.basename(path)}: non-finite numbers at {bad[:3]}")
    for s in stats.get("surfaces", []):
        if any(v is None for v in s.get("radiosity", [])):
            failures.append(f"{os.path.basename(path)}: surface {s.get('name')} has a null radiosity")
            break
    energy = stats.get("energy", {})
    off = energy.get("relative_difference")
    warned = any("power absorbed differs" in w for w in stats.get("warnings", []))
    if energy.get("closed") and not energy.get("truncated") and off is not None \
            and abs(off) > 0.01 and not warned:
        failures.append(f"{os.path.basename(path)}: closed scene off balance by {off:+.3%} without a warning")
    for listed in stats.get("outputs", []):
        if not os.path.exists(listed) and not os.path.exists(os.path.join(os.path.dirname(path), "..", listed)):
            failures.append(f"{os.path.basename(path)}: lists {listed}, which does not exist")
    return failures


def check_pictures(folder, stderr, exposure_given):
    failures = []
    for name in sorted(os.listdir(folder)):
        if name.startswith(".") or not name.endswith(".png") or "_false" in name:
            continue
        extremes = png_extremes(os.path.join(folder, name))
        if extremes is None:
            continue
        lo, hi = extremes
        if hi == 0 and "the picture is black" not in stderr:
            failures.append(f"{name}: all black without a warning")
        if lo == 255 and not exposure_given:
            failures.append(f"{name}: all white at the automatic exposure")
    return failures


def check_set(folder, width):
    """The solve's PNG, EXR and JSON of each name are of one run."""
    failures = []
    for name in sorted(os.listdir(folder)):
        if name.startswith(".") or not name.endswith(".json"):
            continue
        stem = name[:-5]
        png, exr = os.path.join(folder, stem + ".png"), os.path.join(folder, stem + ".exr")
        if os.path.exists(png) and os.path.exists(exr):
            widths = (png_size(png)[0], exr_width(exr))
            if width is not None and widths != (width, width):
                failures.append(f"{stem}: png and exr widths {widths}, asked {width}")
    return failures


def check_tidy(folder):
    """Only the sets' pointers and version folders are hidden."""
    if not os.path.isdir(folder):
        return []
    names = os.listdir(folder)
    pointers = [n for n in names if n.startswith(".") and n.endswith(".outputs")]
    left = []
    for n in names:
        if not n.startswith(".") or n in pointers:
            continue
        owner = next((p for p in pointers if n.startswith(p + "-")), None)
        if owner and os.path.realpath(os.path.join(folder, owner)) == os.path.realpath(os.path.join(folder, n)):
            continue
        left.append(n)
    return [f"left behind in {os.path.basename(folder)}: {left}"] if left else []


def digest_files(folder, skip=()):
    """sha256 of every regular file under `folder` (not following links),
    outside the subfolders named in `skip`."""
    out = {}
    for root, dirs, files in os.walk(folder):
        dirs[:] = [d for d in dirs if d not in skip and not d.startswith(".")]
        for f in files:
            p = os.path.join(root, f)
            if os.path.islink(p) or f.startswith("."):
                continue
            with open(p, "rb") as fh:
                out[p] = hashlib.sha256(fh.read()).hexdigest()
    return out


def check_inputs(before, after_folder, skip=()):
    after = digest_files(after_folder, skip)
    return [f"input {os.path.basename(p)} changed" for p, d in before.items()
            if p in after and after[p] != d] + \
           [f"input {os.path.basename(p)} removed" for p in before if p not in after]
