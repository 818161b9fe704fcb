#!/usr/bin/python3
"""The table of bench/results/scaling.json (run_scaling.py) in Markdown, for the READMEs:
`/usr/bin/python3 bench/scaling_table.py` prints it with the commit, command and load."""
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))


COLUMNS = ["case", "N (1 core / 2 cores)", "1x1 ms/RHS", "1x2 ms/RHS", "2x1 ms/RHS", "1x2 ratio", "2x1 ratio",
           "2x1 ratio per step", "2x1 halo max"]


def table_rows(results):
    """The table's rows (formatted cells) from run_scaling.py's results."""
    def f(x, spec):
        return format(x, spec) if x is not None else "failed"
    rows = []
    for c in results:
        L = c["layouts"]
        n1, n2 = L["1x1"]["N"], L["2x1"]["N"]
        key = "speedup" if c["kind"] == "strong" else "weak_efficiency"
        rows.append([f"{c['kind']}, {c['dim']}D", f"{n1}" if n1 == n2 else f"{n1} / {n2}"]
                    + [f(L[lay]["ms_per_rhs"], ".3f") for lay in ("1x1", "1x2", "2x1")]
                    + [f(L["1x2"][key + "_rhs"], ".3f"), f(L["2x1"][key + "_rhs"], ".3f"), f(L["2x1"][key + "_step"], ".3f"),
                       f(L["2x1"]["halo_max"], ".0f")])
    return rows


def main():
    r = json.load(open(os.path.join(HERE, "results", "scaling.json")))
    print(f"At commit {r['commit']} (`/usr/bin/python3 {r['command']}`, {r['seconds']:.0f} s; medians; load average "
          f"{r['load_average'][0]:.1f} at the start and {r['load_average'][1]:.1f} at the end on 2 cores; table by "
          "`bench/scaling_table.py`):\n")
    print("| " + " | ".join(COLUMNS) + " |")
    print("|" + "---|" * len(COLUMNS))
    for row in table_rows(r["results"]):
        print("| " + " | ".join(row) + " |")
    print("\n(ratio: strong speed-up T(1x1) / T(layout), ideal 2 on two cores; weak efficiency "
          "[T(1x1) / N1] / [T(layout) / N2] / cores, ideal 1.)")


if __name__ == "__main__":
    main()
