#!/usr/bin/python3
"""The evolved kernel range counts the particles whose grad-h factor is not positive.

At -smoothing_length evolved, Omega_i = 1 + (h_i/(D rho_i)) d rho_i/d h_i from one density
pass at the state's h_i; a particle whose range holds no partner has rho_i = m_i w(0, h_i)
= m_i C / h_i^D, so rho_i h_i^D does not grow with h_i and Omega_i = 0. It then takes
Omega_i = 1 (as the solve holds such a particle at its upper bound), which must not be
silent: summary.json counts those particle evaluations (omega_floored, and the most in one
density pass, omega_floored_max_per_rhs) and the run ends with a note on stderr.

The file scene, 2D gas (gamma 2, e 0.5, no viscosity), h = 2, an 8 x 8 lattice of unit
spacing in a periodic 40 x 40 box, to t = 1 at a fixed step 0.05 (Dormand-Prince: 20
steps, about 120 evaluations, 0.1 s; CFL step about 0.6 h/c = 1.2):
- the lattice alone: every particle has partners (Omega > 0): omega_floored 0, no note;
- the lattice and one particle 20 away (beyond the list range h_max h + skin and beyond
  what the lattice's expansion reaches by t = 1): that particle is counted in every density
  pass (at least one count per right-hand side, exactly one per pass), the note names the
  count and the run is otherwise unchanged: the lattice's final positions are the first
  run's bit for bit (the lone particle has no pairs, and the steps are fixed).
"""
import json
import os

from spamrun import Checks, arguments, final_state, run

a = arguments()
c = Checks()
COMMON = ["-scene", "file", "-box_len", "40,40", "-dim", 2, "-h", 2, "-material", "gas", "-gas_gamma", 2,
          "-viscosity", "none", "-smoothing_length", "evolved", "-ts_max_time", 1, "-arkode_fixed_step", 0.05, "-output_interval", 0,
          "-snapshot_interval", 0, "-quiet"]
lattice = [f"{10.5 + i},{10.5 + j},0,0,1,0.5" for i in range(8) for j in range(8)]
got = {}
for name, rows in (("lattice", lattice), ("lone", lattice + ["30.5,30.5,0,0,1,0.5"])):
    path = os.path.join(a.workdir, name + ".csv")
    with open(path, "w") as fh:
        fh.write("x,y,vx,vy,m,e\n" + "\n".join(rows) + "\n")
    out = os.path.join(a.workdir, name)
    final = os.path.join(a.workdir, name + "_final.csv")
    code, _, err = run(a.spam_ark, COMMON + ["-file_path", path, "-final_csv", final], out)
    if not c.check(code == 0, f"{name}: run exits 0 ({err.strip()[-300:]})"):
        c.finish()
    with open(os.path.join(out, "summary.json")) as fh:
        got[name] = (json.load(fh), err, final_state(final))

s, err, _ = got["lattice"]
c.check(s.get("omega_floored") == 0 and s.get("omega_floored_max_per_rhs") == 0 and "Omega <= 0" not in err,
        f"lattice alone: omega_floored {s.get('omega_floored')}, most in one pass {s.get('omega_floored_max_per_rhs')} (0, 0), no note")
s, err, _ = got["lone"]
evals = s["rhs_evals_process"]
c.check(s.get("omega_floored", 0) >= evals and s.get("omega_floored_max_per_rhs") == 1,
        f"lone particle: omega_floored {s.get('omega_floored')} over {evals} right-hand sides (at least one each), "
        f"most in one pass {s.get('omega_floored_max_per_rhs')} (1: that particle alone)")
c.check(f"{s.get('omega_floored')} particle evaluations" in err and "took Omega = 1" in err,
        f"the note on stderr names the count ({err.strip()[-200:]!r})")
ref, lone = got["lattice"][2], got["lone"][2]
diff = max(abs(p[k] - q[k]) for p, q in zip(ref, lone[:len(ref)]) for k in (0, 1))  # x, y
c.check(len(lone) == len(ref) + 1 and diff == 0.0,
        f"the lattice's final positions with the lone particle beside: {diff:.1e} from the lattice alone's (the same steps: bit for bit)")
c.finish()
