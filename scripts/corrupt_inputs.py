"""Corrupted inputs through the room_reverb tool, end to end (docs/reliability.md).

Each target is a file a user hands to a subcommand (metrics, rsao, render, simulate,
compare, room-model, make-capture): its seed is a file of the project's
own (bundled data, a config file, or one the tool writes at the start of the run), and
every run mutates a copy (bit flips, overwritten or inserted bytes, truncation, a range
zeroed or duplicated; in text files also lines dropped or repeated and numbers replaced by
NaN, inf, negatives, huge values) and runs the subcommand on it. A run passes when the
tool exits 0, or 2 with exactly one line on stderr, within the time limit; an exit 1 (an
internal error), a signal, more than one line, or a hang fails, and the input is kept
under OUT/failures/ with the command. Deterministic for a seed. The mutations are drawn
here, not by the fuzzers, and reach the tool's whole path (argument checks, the parsers,
what the parsed values do to the computation and the writers), so they are inputs the
fuzz targets were not grown on.
"""
import argparse
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOOL = os.path.join(REPO, ".ws", "devel", "lib", "room_reverb", "room_reverb")
NUMBERS = re.compile(rb"-?\d+(\.\d+)?([eE][-+]?\d+)?")
ODD_NUMBERS = [b"nan", b"NaN", b"inf", b"-inf", b"-1", b"0", b"-0.0", b"1e308", b"-1e308", b"1e-320",
               b"99999999999999999999", b"4294967296", b"2147483648", b"0x7f", b"", b"1.5.2"]
ODD_BYTES = [b"\x00", b"\xff", b"\x7f", b"\x80", b"\n", b"\r\n", b"\t", b":", b"- ", b"{", b"[", b"\"", b"\\", b"\x1b["]


def mutate(data, rng, text):
    """One to four random mutations of `data` (bytes)."""
    data = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        kinds = ["flip", "overwrite", "insert", "truncate", "zero", "duplicate"]
        if text:
            kinds += ["number", "number", "number", "line_drop", "line_repeat", "odd_bytes"]
        kind = rng.choice(kinds)
        n = len(data)
        if n == 0:
            data += bytes(rng.getrandbits(8) for _ in range(rng.randint(1, 16)))
            continue
        at = rng.randrange(n)
        if kind == "flip":
            for _ in range(rng.randint(1, 20)):
                i = rng.randrange(n)
                data[i] ^= 1 << rng.randrange(8)
        elif kind == "overwrite":
            length = min(n - at, rng.choice([1, 2, 4, 8, 64]))
            data[at:at + length] = bytes(rng.choice([0, 0xFF, 0x7F, 0x80, rng.getrandbits(8)]) for _ in range(length))
        elif kind == "insert":
            data[at:at] = bytes(rng.getrandbits(8) for _ in range(rng.choice([1, 3, 16, 300])))
        elif kind == "truncate":
            del data[rng.randrange(n):]
        elif kind == "zero":
            length = min(n - at, rng.randint(1, max(1, n // 8)))
            data[at:at + length] = bytes(length)
        elif kind == "duplicate":
            length = min(n - at, rng.randint(1, max(1, n // 8)))
            data[at:at] = data[at:at + length]
        elif kind == "number":
            matches = list(NUMBERS.finditer(bytes(data)))
            if matches:
                m = rng.choice(matches)
                data[m.start():m.end()] = rng.choice(ODD_NUMBERS)
        elif kind in ("line_drop", "line_repeat"):
            lines = bytes(data).split(b"\n")
            i = rng.randrange(len(lines))
            if kind == "line_drop":
                del lines[i]
            else:
                lines.insert(i, lines[i])
            data = bytearray(b"\n".join(lines))
        elif kind == "odd_bytes":
            data[at:at] = rng.choice(ODD_BYTES)
    return bytes(data)


def shoebox_meshes(work):
    """A 5 x 4 x 3 m shoebox as AC3D, OBJ and ASCII PLY (plaster walls): the mesh seeds."""
    v = [(x, y, z) for x in (0.0, 5.0) for y in (0.0, 4.0) for z in (0.0, 3.0)]
    # Faces (vertex indices) wound so the normals point into the room.
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = [t for q in quads for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
    paths = {}
    obj = "mtllib none\nusemtl plaster_smooth\n" + "".join(f"v {x} {y} {z}\n" for x, y, z in v)
    obj += "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in tris)
    ply = ("ply\nformat ascii 1.0\ncomment material 0 plaster_smooth\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
           "element face 12\nproperty list uchar int vertex_indices\nproperty int material_index\nend_header\n")
    ply += "".join(f"{x} {y} {z}\n" for x, y, z in v) + "".join(f"3 {a} {b} {c} 0\n" for a, b, c in tris)
    ac = ('AC3Db\nMATERIAL "plaster_smooth" rgb 1 1 1 amb 0.2 0.2 0.2 emis 0 0 0 spec 0 0 0 shi 0 trans 0\n'
          'OBJECT world\nkids 1\nOBJECT poly\nname "room"\nnumvert 8\n')
    ac += "".join(f"{x} {y} {z}\n" for x, y, z in v)
    ac += "numsurf 12\n" + "".join(f"SURF 0x10\nmat 0\nrefs 3\n{a} 0 0\n{b} 0 0\n{c} 0 0\n" for a, b, c in tris)
    ac += "kids 0\n"
    for name, text in (("obj", obj), ("ply", ply), ("ac", ac)):
        paths[name] = os.path.join(work, f"shoebox.{name}")
        with open(paths[name], "w") as f:
            f.write(text)
    return paths


def targets(work):
    """name -> (seed file, is text, command with {in} and {out}, an output path without its extension)."""
    data = os.path.join(REPO, "data")
    dry = os.path.join(work, "dry.wav")
    rsao_yaml = os.path.join(work, "rsao.yaml")
    small_ir = os.path.join(work, "ir.wav")
    church = os.path.join(data, "rirs", "bformat", "st_andrews_church.wav")
    room = os.path.join(data, "sample_room", "acoustic.yaml")
    # Seeds the tool writes: a short dry source, an RSAO, a short first-order response.
    setup = [
        [TOOL, "simulate", "--room", room, "--source", "4.6", "2.9", "1.5", "--listener", "2.7", "2.1", "1.4",
         "--mode", "eyring", "--order", "1", "--duration", "0.3", "--ambisonic-order", "0", "--out", dry],
        [TOOL, "rsao", church, "--format", "fuma", "--yaml", rsao_yaml],
        [TOOL, "simulate", "--room", room, "--source", "4.6", "2.9", "1.5", "--listener", "2.7", "2.1", "1.4",
         "--mode", "eyring", "--order", "1", "--duration", "0.3", "--out", small_ir],
    ]
    capture = os.path.join(work, "capture")
    scene = os.path.join(data, "captures", "plain_office.yaml")
    setup += [
        [TOOL, "make-capture", "--scene", scene, "--out", capture, "--width", "256"],
        [TOOL, "room-model", "--top", os.path.join(capture, "top.png"), "--bottom", os.path.join(capture, "bottom.png"),
         "--out", os.path.join(work, "captured_room.yaml"), "--cloud", os.path.join(work, "cloud.pcd")],
    ]
    for command in setup:
        made = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        if made.returncode != 0:
            raise RuntimeError(f"making a seed failed: {' '.join(command)}: {made.stderr.decode(errors='replace')}")
    top = os.path.join(capture, "top.png")
    meshes = shoebox_meshes(work)
    measurements = os.path.join(work, "measurements.yaml")
    with open(measurements, "w") as f:
        f.write(f"room: {room}\npairs:\n  - {{label: rig, file: {small_ir}, format: ambix, source_m: [4.6, 2.9, 1.5], "
                "receiver_m: [2.7, 2.1, 1.4]}\n")
    poses = os.path.join(work, "poses.csv")
    with open(poses, "w") as f:
        f.write("t_s,x_m,y_m,z_m,qx,qy,qz,qw\n0,2.7,2.1,1.4,0,0,0,1\n0.3,3.2,2.3,1.4,0,0,0.3826834,0.9238795\n")
    simulate_tail = ["--source", "1.2", "1.1", "1.5", "--listener", "3.4", "2.6", "1.6", "--mode", "eyring",
                     "--order", "1", "--duration", "0.2", "--ambisonic-order", "0", "--out", "{out}.wav"]
    return {
        "wav_metrics": (os.path.join(data, "rirs", "omni", "clap_seminar_room.wav"), False,
                        [TOOL, "metrics", "{in}"]),
        "bformat_rsao": (church, False, [TOOL, "rsao", "{in}", "--format", "fuma", "--yaml", "{out}.yaml"]),
        "ambisonic_rir_render": (small_ir, False, [TOOL, "render", "--source", dry, "--ambisonic-rir", "{in}",
                                                   "--out", "{out}.wav"]),
        "dry_source_render": (dry, False, [TOOL, "render", "--source", "{in}", "--ambisonic-rir", small_ir,
                                           "--out", "{out}.wav"]),
        "sofa_render": (os.path.join(data, "hrtf", "FHK_HRIR_L2354.sofa"), False,
                        [TOOL, "render", "--source", dry, "--ambisonic-rir", small_ir, "--hrtf", "{in}",
                         "--out", "{out}.wav"]),
        "rsao_yaml_render": (rsao_yaml, True, [TOOL, "render", "--source", dry, "--rsao", "{in}", "--out", "{out}.wav"]),
        "poses_csv_render": (poses, True, [TOOL, "render", "--source", dry, "--rsao", rsao_yaml, "--rig", "2.7",
                                           "2.1", "1.4", "--poses", "{in}", "--out", "{out}.wav"]),
        "room_yaml_simulate": (room, True, [TOOL, "simulate", "--room", "{in}", "--source", "4.6", "2.9", "1.5",
                                            "--listener", "2.7", "2.1", "1.4", "--mode", "eyring", "--order", "1",
                                            "--duration", "0.2", "--ambisonic-order", "0", "--out", "{out}.wav"]),
        "materials_yaml_simulate": (os.path.join(REPO, "config", "materials.yaml"), True,
                                    [TOOL, "simulate", "--room", room, "--materials", "{in}", "--source", "4.6",
                                     "2.9", "1.5", "--listener", "2.7", "2.1", "1.4", "--mode", "eyring", "--order",
                                     "1", "--duration", "0.2", "--ambisonic-order", "0", "--out", "{out}.wav"]),
        "mesh_ac_simulate": (meshes["ac"], True, [TOOL, "simulate", "--mesh", "{in}"] + simulate_tail),
        "mesh_obj_simulate": (meshes["obj"], True, [TOOL, "simulate", "--mesh", "{in}"] + simulate_tail),
        "mesh_ply_simulate": (meshes["ply"], True, [TOOL, "simulate", "--mesh", "{in}"] + simulate_tail),
        "measurements_compare": (measurements, True, [TOOL, "compare", "--measurements", "{in}", "--mode", "eyring",
                                                      "--order", "1", "--duration", "0.3", "--threads", "1"]),
        "top_png_room_model": (top, False, [TOOL, "room-model", "--top", "{in}", "--bottom",
                                            os.path.join(capture, "bottom.png"), "--out", "{out}.yaml"]),
        "cloud_pcd_room_model": (os.path.join(work, "cloud.pcd"), False, [TOOL, "room-model", "--top", top, "--depth",
                                                                          "{in}", "--out", "{out}.yaml"]),
        "range_tiff_room_model": (os.path.join(capture, "top_range.tiff"), False,
                                  [TOOL, "room-model", "--top", top, "--depth", "{in}", "--out", "{out}.yaml"]),
        "scene_yaml_make_capture": (scene, True, [TOOL, "make-capture", "--scene", "{in}", "--out", "{out}.d",
                                                  "--width", "128"]),
    }


def run_one(command, timeout_s):
    start = time.monotonic()
    try:
        p = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=timeout_s)
    except subprocess.TimeoutExpired:
        return "hang", f"no answer in {timeout_s:.0f} s", time.monotonic() - start
    except OSError as e:  # the tool itself missing or being rebuilt
        return "failed", f"could not run the tool: {e}", time.monotonic() - start
    elapsed = time.monotonic() - start
    stderr = p.stderr.decode("utf-8", "replace")
    lines = [l for l in stderr.split("\n") if l.strip()]
    if p.returncode < 0:
        return "signal", f"killed by signal {-p.returncode}", elapsed
    if p.returncode == 0:
        return "ok", "", elapsed
    if p.returncode == 2 and len(lines) == 1:
        return "refused", lines[0], elapsed
    return "failed", f"exit {p.returncode}, {len(lines)} stderr lines: {stderr[:400]!r}", elapsed


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=20, help="mutated inputs per target (default 20)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds before a run counts as a hang")
    parser.add_argument("--out", default=os.path.join(REPO, ".ws", "corrupt_inputs"))
    parser.add_argument("--junit", help="also write a JUnit XML file (one case per target)")
    parser.add_argument("--list", action="store_true", help="print the targets and exit")
    parser.add_argument("targets", nargs="*")
    args = parser.parse_args()
    if not os.access(TOOL, os.X_OK):
        print("corrupt-inputs: the tool is not built; run scripts/build first", file=sys.stderr)
        return 2
    shutil.rmtree(args.out, ignore_errors=True)
    os.makedirs(os.path.join(args.out, "failures"))
    work = tempfile.mkdtemp(prefix="corrupt_inputs_")
    try:
        all_targets = targets(work)
        if args.list:
            print("\n".join(all_targets))
            return 0
        chosen = args.targets or list(all_targets)
        unknown = [t for t in chosen if t not in all_targets]
        if unknown:
            print(f"corrupt-inputs: no target {unknown[0]} (--list names them)", file=sys.stderr)
            return 2
        results = {}
        for name in chosen:
            seed_file, text, template = all_targets[name]
            with open(seed_file, "rb") as f:
                seed_data = f.read()
            rng = random.Random(f"{args.seed}:{name}")
            suffix = os.path.splitext(seed_file)[1]
            counts = {"ok": 0, "refused": 0, "failed": 0, "signal": 0, "hang": 0}
            failures = []
            slowest = 0.0
            for k in range(args.runs):
                corrupt = os.path.join(work, f"{name}_{k}{suffix}")
                with open(corrupt, "wb") as f:
                    f.write(mutate(seed_data, rng, text))
                out = os.path.join(work, f"{name}_out")  # each command adds its own extension
                command = [a.replace("{in}", corrupt).replace("{out}", out) for a in template]
                outcome, detail, elapsed = run_one(command, args.timeout)
                slowest = max(slowest, elapsed)
                counts[outcome] += 1
                if outcome in ("failed", "signal", "hang"):
                    kept = os.path.join(args.out, "failures", os.path.basename(corrupt))
                    shutil.copy(corrupt, kept)
                    failures.append(f"{kept}: {outcome}: {detail}\n  {' '.join(command)}")
                os.remove(corrupt)
            results[name] = (counts, failures, slowest)
            bad = counts["failed"] + counts["signal"] + counts["hang"]
            print(f"{name}: {args.runs} inputs, {counts['ok']} accepted, {counts['refused']} refused in one line, "
                  f"{bad} failed (slowest {slowest:.1f} s)", flush=True)
            for line in failures:
                print("  " + line)
        if args.junit:
            write_junit(args.junit, results)
        total_bad = sum(r[0]["failed"] + r[0]["signal"] + r[0]["hang"] for r in results.values())
        return 1 if total_bad else 0
    finally:
        shutil.rmtree(work, ignore_errors=True)


def write_junit(path, results):
    from xml.sax.saxutils import escape
    cases = []
    for name, (counts, failures, slowest) in results.items():
        body = ""
        if failures:
            body = f'<failure message="{len(failures)} failed">{escape(chr(10).join(failures))}</failure>'
        cases.append(f'<testcase classname="corrupt_inputs" name="{name}" time="{slowest:.2f}">{body}</testcase>')
    failed = sum(1 for r in results.values() if r[1])
    with open(path, "w") as f:
        f.write(f'<?xml version="1.0"?>\n<testsuite name="corrupt_inputs" tests="{len(results)}" failures="{failed}">'
                + "".join(cases) + "</testsuite>\n")


if __name__ == "__main__":
    sys.exit(main())
