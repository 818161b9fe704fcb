"""Bad input: one line on stderr naming the option (or file:line), the value and what is
allowed; exit code 2; no output directory, no crash. A run that blows up is a result:
status "unstable", exit code 3, the particle and time named, the last good state kept."""
import json
import os
from spamrun import Checks, arguments, run

a = arguments()
c = Checks()
w = a.workdir


def write(name, text):
    path = os.path.join(w, name)
    with open(path, "w") as f:
        f.write(text)
    return path


good = write("good.csv", "x,y,vx,vy\n" + "".join(f"{i + 0.5},{j + 0.5},0,0\n" for j in range(8) for i in range(8)))
file_scene = ["-scene", "file", "-box_len", "8,8"]
cases = [
    ("unknown scene", ["-scene", "vortex"], ["-scene", "vortex", "allowed: expansion, file"]),
    ("unknown table", ["-arkode_table", "RK4"], ["-arkode_table", "RK4", "ARKODE_DORMAND_PRINCE_7_4_5"]),
    ("unknown controller", ["-arkode_adapt", "pd"], ["-arkode_adapt", "pd", "pid, pi, i, expgus, impgus"]),
    ("zero lattice size", ["-expansion_n", 0], ["-expansion_n", "'0'", "positive"]),
    ("negative lattice size", ["-expansion_n", -4], ["-expansion_n", "'-4'", "positive"]),
    ("zero h", ["-h", 0], ["-h", "'0'", "positive"]),
    ("negative h", ["-h", -2.5], ["-h", "'-2.5'", "positive"]),
    ("h not a number", ["-h", "abc"], ["-h", "'abc'", "number"]),
    ("dimension 4", ["-dim", 4], ["-dim", "'4'", "1, 2 or 3"]),
    ("box narrower than 2h (expansion)", ["-expansion_n", 2, "-h", 3], ["expansion_n", "'4'", "at least 2h"]),
    ("box narrower than 2h (file)", file_scene[:-1] + ["5,8", "-file_path", good], ["-box_len", "'5'", "at least 2h"]),
    ("skin of half the box", ["-expansion_n", 8, "-neighbour_skin", 9], ["-neighbour_skin", "'9.'", "below half the periodic box edge"]),
    ("zero threads", ["-threads", 0], ["-threads", "'0'", "from 1 to 256"]),
    ("zero rtol", ["-ts_rtol", 0], ["-ts_rtol", "'0'", "positive"]),
    ("negative atol", ["-ts_atol", -1e-9], ["-ts_atol", "'-1e-09'", "positive"]),
    ("negative fixed step", ["-arkode_fixed_step", -0.1], ["-arkode_fixed_step", "'-0.1'"]),
    ("file scene without a file", file_scene, ["-file_path", "needs a CSV"]),
    ("file scene without a box", ["-scene", "file", "-file_path", good], ["-box_len", "box edge lengths"]),
    ("unreadable file", file_scene + ["-file_path", os.path.join(w, "missing.csv")], ["-file_path", "missing.csv", "No such file"]),
    ("wrong header", file_scene + ["-file_path", write("h.csv", "x,y,z\n1,2,3\n")], ["h.csv:1", "'x,y,z'", "x,y,vx,vy"]),
    ("short line", file_scene + ["-file_path", write("s.csv", "x,y,vx,vy\n1,2,0,0\n1,2,3\n")], ["s.csv:3", "'1,2,3'", "expected 4", "found 3"]),
    ("not a number", file_scene + ["-file_path", write("n.csv", "x,y,vx,vy\n1,2,0,0\n1,two,0,0\n")], ["n.csv:3", "'1,two,0,0'", "field 2"]),
    ("infinite value", file_scene + ["-file_path", write("i.csv", "x,y,vx,vy\n1,2,inf,0\n")], ["i.csv:2", "field 3", "finite"]),
    ("unequal masses", file_scene + ["-file_path", write("m.csv", "x,y,vx,vy,m\n1,2,0,0,1\n3,2,0,0,2\n")], ["m.csv:3", "same mass"]),
    ("unknown -ts_type", ["-ts_type", "leapfrog"], ["-ts_type", "'leapfrog'", "arkode, cvode, rk, ssp, euler, basicsymplectic"]),
    ("implicit -ts_type", ["-ts_type", "beuler"], ["-ts_type", "'beuler'", "allowed"]),
    ("unknown RK scheme", ["-ts_type", "rk", "-ts_rk_type", "9x"], ["-ts_rk_type", "'9x'", "5dp"]),
    ("unknown Verlet ordering", ["-ts_type", "basicsymplectic", "-ts_basicsymplectic_type", "vv"], ["-ts_basicsymplectic_type", "'vv'", "kdk, dkd"]),
    ("RK without error estimate, adaptive", ["-ts_type", "rk", "-ts_rk_type", "4", "-ts_adapt_type", "basic"], ["-ts_rk_type", "'4'", "no embedded error estimate"]),
    ("unknown TS adaptor", ["-ts_type", "rk", "-ts_adapt_type", "magic"], ["-ts_adapt_type", "'magic'", "none, basic, dsp"]),
    ("CVODE order 13", ["-ts_type", "cvode", "-cvode_max_order", 13], ["-cvode_max_order", "'13'", "1 to 12"]),
    ("negative CFL number", ["-step_cfl", -0.5], ["-step_cfl", "'-0.5'", "positive"]),
    ("no particles", file_scene + ["-file_path", write("e.csv", "x,y,vx,vy\n")], ["-file_path", "no particles"]),
]
for k, (name, args, needles) in enumerate(cases):
    out = os.path.join(w, f"out{k}")
    code, stdout, err = run(a.spam_ark, args, out)
    lines = err.strip().splitlines()
    ok = (code == 2 and len(lines) == 1 and lines[0].startswith("spam-ark: error: ")
          and all(n in lines[0] for n in needles) and not os.path.exists(out))
    c.check(ok, f"{name}: exit {code}, stderr {lines}, output dir {'absent' if not os.path.exists(out) else 'PRESENT'}")

# A particle with v = 1e308 and a step of 2 overflows its position at the DP stage
# c = 0.8 of step 1 (t = 1.6): a clean stop.
blow = write("blow.csv", "x,y,vx,vy\n" + "".join(f"{i + 0.5},{j + 0.5},{1e308 if (i, j) == (3, 4) else 0.0!r},0\n" for j in range(8) for i in range(8)))
out = os.path.join(w, "unstable")
code, stdout, err = run(a.spam_ark, file_scene + ["-file_path", blow, "-arkode_fixed_step", 2, "-ts_max_time", 10], out)
with open(os.path.join(out, "summary.json")) as f:
    s = json.load(f)
c.check(code == 3, f"overflowing run exits with code 3 (got {code}), not a signal")
c.check(s["status"] == "unstable" and "particle 35" in s["reason"] and "t = 1.6" in s["reason"] and "step 1" in s["reason"], f"summary names the particle and time: {s['reason']}")
c.check("unstable" in stdout and "particle 35" in stdout, "the monitor says why it stopped")
c.check(os.path.exists(os.path.join(out, "particles_last_good.csv")), "the last good state is kept as a snapshot")
c.finish()
