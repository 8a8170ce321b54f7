"""Summary tables of scripts/demo: the sample room's five conditions against the reference,
and the bundled real rooms' RSAO against their measured RIR. Reads the metrics JSON files
the demo wrote (room_reverb metrics --json). Standard library only.
Usage: demo_summary.py DEMO_OUTPUT_DIR"""
import json
import os
import sys

BANDS = [125, 250, 500, 1000, 2000, 4000]
# "corrected": the visual route's room model after the diagnosis against the measured RIR
# (the closed loop); the others are the paper's five conditions.
CONDITIONS = ["reference", "rsao", "accurate", "corrected", "fast", "wrong_room"]


def band_values(path, key):
    with open(path) as f:
        bands = {round(b["center_hz"]): b for b in json.load(f)["bands"]}
    return [bands.get(hz, {}).get(key) for hz in BANDS]


def mean_relative_error(values, reference):
    errors = [abs(v - r) / r for v, r in zip(values, reference) if v is not None and r]
    return 100.0 * sum(errors) / len(errors) if errors else float("nan")


def mean_difference(values, reference):
    errors = [abs(v - r) for v, r in zip(values, reference) if v is not None and r is not None]
    return sum(errors) / len(errors) if errors else float("nan")


def cell(v, fmt):
    return "-" if v is None else fmt.format(v)


def main(out):
    metrics = os.path.join(out, "sample_room", "metrics")
    t20 = {c: band_values(os.path.join(metrics, c + ".json"), "t20_s") for c in CONDITIONS}
    c80 = {c: band_values(os.path.join(metrics, c + ".json"), "c80_db") for c in CONDITIONS}
    print("## Sample room: the conditions' room responses (W channel)\n")
    print("`accurate` simulates the visual route's room model; `corrected` the same model after the diagnosis "
          "against the measured RIR (sample_room/diagnosis/report.md).\n")
    print("| condition | " + " | ".join(f"T20 {hz} Hz [s]" for hz in BANDS) + " | mean abs T20 error vs reference | mean abs C80 error [dB] |")
    print("|---|" + "---:|" * (len(BANDS) + 2))
    for c in CONDITIONS:
        row = " | ".join(cell(v, "{:.2f}") for v in t20[c])
        err = mean_relative_error(t20[c], t20["reference"])
        derr = mean_difference(c80[c], c80["reference"])
        print(f"| {c} | {row} | {err:.1f} % | {derr:.2f} |")
    order = sorted((c for c in CONDITIONS if c != "reference"), key=lambda c: mean_relative_error(t20[c], t20["reference"]))
    print("\nClosest to the reference in T20 first: " + ", ".join(order) + ".")

    print("\n## Bundled real rooms: measured RIR against its RSAO resynthesis (W channel)\n")
    print("| room | T20 measured 500/1k/2k Hz [s] | T20 RSAO [s] | mean abs T20 error | mean abs C80 error [dB] |")
    print("|---|---|---|---:|---:|")
    rooms = os.path.join(out, "real_rooms")
    for name in sorted(os.listdir(rooms)):
        ref = os.path.join(rooms, name, "metrics_reference.json")
        rsao = os.path.join(rooms, name, "metrics_rsao.json")
        if not (os.path.exists(ref) and os.path.exists(rsao)):
            continue
        t_ref, t_rsao = band_values(ref, "t20_s"), band_values(rsao, "t20_s")
        c_ref, c_rsao = band_values(ref, "c80_db"), band_values(rsao, "c80_db")
        mid = slice(2, 5)
        print(f"| {name} | {' / '.join(cell(v, '{:.2f}') for v in t_ref[mid])} | "
              f"{' / '.join(cell(v, '{:.2f}') for v in t_rsao[mid])} | "
              f"{mean_relative_error(t_rsao, t_ref):.1f} % | {mean_difference(c_rsao, c_ref):.2f} |")


if __name__ == "__main__":
    main(sys.argv[1])
