#!/usr/bin/env python3
"""Markdown tables of work-precision CSVs (wire_sim work-precision).

usage: work_precision_table.py "LABEL=DIR_OR_CSV" [...] > tables.md

One table per CSV: method, setting, shape error / d, bulging error, wall time,
real-time factor; failed runs with the first clause of their reason.
"""
import csv
import os
import sys


def sci(x):
    return f"{float(x):.1e}"


def table(label, path):
    if os.path.isdir(path):
        path = os.path.join(path, "work_precision.csv")
    with open(path, newline="") as f:
        lines = f.read().splitlines()
    rows = list(csv.DictReader(l for l in lines if not l.startswith("#")))
    ref = [l[2:] for l in lines if l.startswith("# reference")]
    out = [f"{label}" + (f" ({ref[0]}):" if ref else ":"), "",
           "| method | setting | shape error / d | bulging error | wall time [s] | real-time factor |",
           "|---|---|---|---|---|---|"]
    for r in rows:
        if r["shape_error_rel_diameter"] == "failed":
            why = r.get("error", "").split(";")[0].replace("|", "/")
            out.append(f"| {r['method']} | {r['setting']} | failed: {why} | | "
                       f"{float(r['wall_time_s']):.1f} | |")
            continue
        shape = float(r["shape_error_rel_diameter"])
        out.append(f"| {r['method']} | {r['setting']} | {sci(shape)}"
                   f"{' (wrong)' if shape > 1 else ''} | {sci(r['bulging_error_rel'])} | "
                   f"{float(r['wall_time_s']):.1f} | {float(r['real_time_factor']):.2g} |")
    return "\n".join(out)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    print("\n\n".join(table(*arg.split("=", 1)) for arg in sys.argv[1:]))


if __name__ == "__main__":
    main()
