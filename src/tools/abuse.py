#!/usr/bin/python3
"""The abuse suite: faults and extremes a winding cell meets, on
config/scenes/two_layers.yaml (50 turns in 2 layers of 25 at 1200 rpm and
30 N, 3 mm flanges that hold 3 layers, 75 turns), each with the outcome it
must have: it finishes, or it is refused or stops with a named cause
(issue 57, beside the robustness suite of random coils).

usage:
  abuse.py run WIRE_SIM OUT_DIR [--budget SECONDS]
      runs each case as a sweep of one case (wire_sim sweep, one at a time,
      as this process runs: e.g. under taskset) and writes OUT_DIR/abuse.csv
  abuse.py report OUT_DIR DOC
      appends the table to DOC (docs/ROBUSTNESS.md); exits 1 when a case's
      outcome is not the expected one
"""
import csv
import io
import os
import subprocess
import sys

SCENE = "config/scenes/two_layers.yaml"

# name, what, scene overrides, expected outcome ("finishes", or
# "refused: TEXT" / "stops: TEXT" with TEXT in the message).
CASES = [
    (
        "traverse_stall",
        "the traverse stalls at turn 10 for 10 turns (60 turns in all)",
        ["process.turns=60", "process.traverse_stall_turn=10", "process.traverse_stall_turns=10"],
        "finishes",
    ),
    (
        "past_plan",
        "wound 30 % past its 2 planned layers (65 turns: a third layer)",
        ["process.turns=65"],
        "finishes",
    ),
    (
        "over_full",
        "100 turns on a bobbin that holds 75",
        ["process.turns=100"],
        "refused: the bobbin holds 3 layers (75 turns)",
    ),
    (
        "over_the_rim",
        "a 26 mm traverse stroke past flanges 20 mm apart and 1 mm high (25 turns, one layer)",
        [
            "process.layers=1",
            "process.turns=25",
            "core.flange_height=0.001",
            "core.flange_spacing=0.02",
        ],
        "stops: wire went over the second flange",
    ),
    (
        "core_reversed",
        "the core reversed for a turn at t = 1 s (2 s in all)",
        [
            "process.duration=2",
            "process.commands=[{time: 1.0, core_speed_rpm: -1200},"
            " {time: 1.05, core_speed_rpm: 1200}]",
        ],
        "finishes",
    ),
    (
        "tension_drop",
        "the tension dropped to 1 N at t = 1 s and restored at 1.5 s",
        ["process.commands=[{time: 1.0, tension: 1}, {time: 1.5, tension: 30}]"],
        "finishes",
    ),
    ("rpm_6000", "6,000 rpm (the setpoint limit)", ["process.core_speed_rpm=6000"], "finishes"),
    (
        "mu_s_0.6",
        "static friction 0.6 (kinetic 0.5)",
        ["contact.static_friction=0.6", "contact.kinetic_friction=0.5"],
        "finishes",
    ),
]

FIELDS = ["case", "status", "message", "sim_time_s", "real_time_factor", "slowest_stretch"]


def one_case_csv(overrides):
    keys = [o.split("=", 1)[0] for o in overrides]
    values = [o.split("=", 1)[1] for o in overrides]
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(keys)
    w.writerow(values)
    return out.getvalue()


def run(wire_sim, out_dir, budget):
    os.makedirs(out_dir, exist_ok=True)
    rows = []
    for name, _, overrides, _ in CASES:
        case_dir = os.path.join(out_dir, name)
        os.makedirs(case_dir, exist_ok=True)
        cases = os.path.join(case_dir, "case.csv")
        with open(cases, "w") as f:
            f.write(one_case_csv(overrides))
        sweep = os.path.join(case_dir, "sweep")
        p = subprocess.run(
            [wire_sim, "sweep", "--scene", SCENE, "--cases", cases, "--jobs", "1",
             "--budget", str(budget), "--out", sweep],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        )
        row = {"case": name}
        results = os.path.join(sweep, "results.csv")
        if os.path.exists(results):
            with open(results) as f:
                r = next(csv.DictReader(f))
            row["status"] = r["status"]
            row["message"] = r.get("error", "")
            row["sim_time_s"] = r.get("sim_time_s", "")
            row["real_time_factor"] = r.get("real_time_factor", "")
            row["slowest_stretch"] = r.get("slowest_stretch.real_time_factor", "")
        else:
            # Refused before anything ran: the scene's own message.
            lines = [ln for ln in p.stdout.splitlines() if ln.strip()]
            row["status"] = "refused"
            row["message"] = lines[-1] if lines else "exit status %d" % p.returncode
        rows.append(row)
        print("abuse: %s: %s %s" % (name, row["status"], row.get("message", "")), flush=True)
    with open(os.path.join(out_dir, "abuse.csv"), "w") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS, lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    return 0


def met(expected, row):
    if expected == "finishes":
        return row["status"] == "ok"
    kind, text = expected.split(": ", 1)
    status = "refused" if kind == "refused" else "failed"
    return row["status"] == status and text in row["message"]


def number(v, spec):
    try:
        return spec % float(v)
    except (TypeError, ValueError):
        return ""


def report(out_dir, doc):
    with open(os.path.join(out_dir, "abuse.csv")) as f:
        got = {r["case"]: r for r in csv.DictReader(f)}
    md = [
        "",
        "## The abuse suite",
        "",
        "Generated by `make robustness` (src/tools/abuse.py); do not edit by hand.",
        "Faults and extremes on `%s` (50 turns in 2 layers of 25 at" % SCENE,
        "1200 rpm and 30 N; its 3 mm flanges hold 3 layers, 75 turns), one at a time",
        "on one core, each with the outcome it must have. Slowest stretch: the",
        "real-time factor of the 0.05 s of simulated time that ran slowest.",
        "",
        "| case | what | expected | outcome | simulated [s] | real-time factor |"
        " slowest stretch | message |",
        "|---|---|---|---|---|---|---|---|",
    ]
    bad = 0
    for name, what, _, expected in CASES:
        r = got.get(name)
        if r is None:
            md.append("| %s | %s | %s | **not run** | | | | |" % (name, what, expected))
            bad += 1
            continue
        ok = met(expected, r)
        bad += not ok
        outcome = ("as expected (%s)" if ok else "**not as expected (%s)**") % r["status"]
        md.append(
            "| %s | %s | %s | %s | %s | %s | %s | %s |"
            % (name, what, expected, outcome, number(r["sim_time_s"], "%.3f"),
               number(r["real_time_factor"], "%.3g"), number(r["slowest_stretch"], "%.3g"),
               r["message"].replace("|", "/"))
        )
    md.append("")
    md.append("**%d of %d abuse cases as expected.**" % (len(CASES) - bad, len(CASES)))
    md.append("")
    with open(doc, "a") as f:
        f.write("\n".join(md))
    print("abuse: %d of %d cases as expected" % (len(CASES) - bad, len(CASES)))
    return 0 if bad == 0 else 1


def main(argv):
    if len(argv) >= 4 and argv[1] == "run":
        budget = 200
        if len(argv) == 6 and argv[4] == "--budget":
            budget = float(argv[5])
        elif len(argv) != 4:
            sys.exit(__doc__)
        return run(argv[2], argv[3], budget)
    if len(argv) == 4 and argv[1] == "report":
        return report(argv[2], argv[3])
    sys.exit(__doc__)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
