#!/usr/bin/python3
"""Bad input: one line on stderr naming the option (or file:line), the value and what is
allowed; exit code 2; no output directory, no crash. A run that blows up is a result:
status "unstable", exit code 3, the particle and time named, the last good state kept."""
import json
import os
import shutil
import subprocess
from spamrun import Checks, Runner, arguments, kernel_names, mpiexec_env

a = arguments()
c = Checks()
w = a.workdir
# The runs in forked children of the fork server (spamrun.Runner); those that need a process
# of their own (the address-space limit, several ranks) start spam-ark.
runner = Runner(a.spam_ark, w)


def write(name, text):
    path = os.path.join(w, name)
    with open(path, "w") as f:
        f.write(text)
    return path


# The kernels as -help lists them: an unknown name must be refused with exactly this list.
kernels = kernel_names(a.spam_ark, runner)
c.check("lucy" in kernels and len(kernels) == len(set(kernels)), f"-help lists the kernels {kernels}")
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
    ("unknown kernel", ["-kernel", "wendland"], ["-kernel", "'wendland'", "allowed: " + ", ".join(kernels)]),
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
    ("wrong header", file_scene + ["-file_path", write("h.csv", "x,y,z\n1,2,3\n")], ["h.csv:1", "'x,y,z'", "column z needs -dim 3"]),
    ("short line", file_scene + ["-file_path", write("s.csv", "x,y,vx,vy\n1,2,0,0\n1,2,3\n")], ["s.csv:3", "'1,2,3'", "expected 4", "found 3"]),
    ("not a number", file_scene + ["-file_path", write("n.csv", "x,y,vx,vy\n1,2,0,0\n1,two,0,0\n")], ["n.csv:3", "'1,two,0,0'", "field 2"]),
    ("infinite value", file_scene + ["-file_path", write("i.csv", "x,y,vx,vy\n1,2,inf,0\n")], ["i.csv:2", "field 3", "finite"]),
    ("non-positive mass", file_scene + ["-file_path", write("m.csv", "x,y,vx,vy,m\n1,2,0,0,1\n3,2,0,0,0\n")], ["m.csv:3", "mass m = 0", "positive"]),
    # A subnormal mass ran "ok" with zero energies and a NaN entropy: refused as -mass 4.9e-324 is.
    ("subnormal mass", file_scene + ["-file_path", write("sm.csv", "x,y,vx,vy,m\n1,2,0,0,1\n3,2,0,0,4.9e-324\n")], ["sm.csv:3", "mass m = 4.9406564584124654e-324", "subnormal"]),
    ("unknown -ts_type", ["-ts_type", "leapfrog"], ["-ts_type", "'leapfrog'", "arkode, arkode_imex, cvode, rk, ssp, euler, basicsymplectic"]),
    ("IMEX without diffusion to treat apart", ["-ts_type", "arkode_imex"], ["-ts_type", "'arkode_imex'", "-diffusion_form pair", "model isentrope"]),
    ("unknown IMEX pair", ["-ts_type", "arkode_imex", "-arkode_imex_table", "ARK2"], ["-arkode_imex_table", "'ARK2'", "ARK324L2SA, ARK436L2SA"]),
    ("IMEX Krylov dimension 0", ["-ts_type", "arkode_imex", "-arkode_imex_krylov_dim", 0], ["-arkode_imex_krylov_dim", "'0'", "1 to 500"]),
    ("implicit -ts_type", ["-ts_type", "beuler"], ["-ts_type", "'beuler'", "allowed"]),
    ("unknown RK scheme", ["-ts_type", "rk", "-ts_rk_type", "9x"], ["-ts_rk_type", "'9x'", "5dp"]),
    ("unknown Verlet ordering", ["-ts_type", "basicsymplectic", "-ts_basicsymplectic_type", "vv"], ["-ts_basicsymplectic_type", "'vv'", "kdk, dkd"]),
    ("RK without error estimate, adaptive", ["-ts_type", "rk", "-ts_rk_type", "4", "-ts_adapt_type", "basic"], ["-ts_rk_type", "'4'", "no embedded error estimate"]),
    ("unknown TS adaptor", ["-ts_type", "rk", "-ts_adapt_type", "magic"], ["-ts_adapt_type", "'magic'", "none, basic, dsp"]),
    ("CVODE order 13", ["-ts_type", "cvode", "-cvode_max_order", 13], ["-cvode_max_order", "'13'", "1 to 12"]),
    ("negative CFL number", ["-step_cfl", -0.5], ["-step_cfl", "'-0.5'", "positive"]),
    ("no particles", file_scene + ["-file_path", write("e.csv", "x,y,vx,vy\n")], ["-file_path", "no particles"]),
]

# Hostile particle files: every malformed or out-of-range line is
# refused naming file:line; anything but a regular file is refused at once.
hdr = "x,y,vx,vy\n1,2,0,0\n"
fifo = os.path.join(w, "fifo.csv")
os.mkfifo(fifo)
os.mkdir(os.path.join(w, "dir.csv"))
with open(os.path.join(w, "nul.csv"), "wb") as f:
    f.write(b"x,y,vx,vy\n1,2,0,0\n1,2\0,0,0\n")
cases += [
    ("blank field", file_scene + ["-file_path", write("ws.csv", hdr + "1, ,0,0\n")], ["ws.csv:3", "'1, ,0,0'", "field 2 is empty"]),
    ("tab-only last field", file_scene + ["-file_path", write("tab.csv", hdr + "1,2,0,\t\n")], ["tab.csv:3", "field 4 is empty"]),
    ("5000-byte line", file_scene + ["-file_path", write("long.csv", hdr + "1." + "0" * 5000 + ",2,0,0\n")], ["long.csv:3", "longer than 4095 bytes", "..."]),
    ("long comment", file_scene + ["-file_path", write("comm.csv", "x,y,vx,vy\n#" + "c" * 4200 + "1,2,0,0\n1,2,0,0\n")], ["comm.csv:2", "longer than 4095 bytes"]),
    ("NUL byte", file_scene + ["-file_path", os.path.join(w, "nul.csv")], ["nul.csv:3", "NUL byte"]),
    ("outside the periodic box", file_scene + ["-file_path", write("out.csv", hdr + "9.5,2,0,0\n")], ["out.csv:3", "x = 9.5", "outside the box", "periodic"]),
    ("outside the open box", file_scene + ["-periodic", "0,0", "-file_path", write("open.csv", hdr + "2,-0.5,0,0\n")], ["open.csv:3", "y = -0.5", "outside the box", "open"]),
    ("coordinate 1e15", file_scene + ["-file_path", write("far.csv", hdr + "1e15,2,0,0\n")], ["far.csv:3", "x = 1e+15", "outside the box"]),
    ("FIFO as -file_path", file_scene + ["-file_path", fifo], ["-file_path", "fifo.csv", "FIFO"]),
    ("directory as -file_path", file_scene + ["-file_path", os.path.join(w, "dir.csv")], ["-file_path", "directory"]),
    ("device as -file_path", file_scene + ["-file_path", "/dev/null"], ["-file_path", "/dev/null", "character device"]),
    ("box far from the origin", file_scene + ["-box_lo", "1e11,0", "-file_path", good], ["box corner x", "1e+11", "within 1e9 h"]),
    ("-box_lo nan (file scene)", file_scene + ["-box_lo", "nan", "-file_path", good], ["-box_lo", "finite"]),
    ("-box_len 8,nan (file scene)", file_scene[:-1] + ["8,nan", "-file_path", good], ["-box_len", "finite"]),
    # Sizes whose products overflow a 32-bit int.
    ("expansion_n 100570", ["-expansion_n", 100570], ["-expansion_n", "'100570'", "1.01e+10 particles", "at most"]),
    ("3D expansion_n 600", ["-dim", 3, "-expansion_n", 600], ["-expansion_n", "'600'", "2.16e+08 particles"]),
    ("tensile_nx 2147483647", ["-scene", "tensile", "-tensile_nx", 2147483647], ["-tensile_nx", "2147483647", "particles", "at most"]),
    ("planewave 100000 x 100000", ["-scene", "planewave", "-planewave_nx", 100000, "-planewave_ny", 100000], ["-planewave_nx", "1e+10 particles"]),
    ("chain_n 2000000000", ["-dim", 1, "-scene", "chain", "-chain_n", 2000000000], ["-chain_n", "'2000000000'", "particles"]),
    ("rotor_speed 4.9e-324", ["-scene", "rotor", "-rotor_speed", "4.9e-324"], ["-rotor_speed", "'4.9", "1e-6 to 10"]),
    ("rotor_gap 0", ["-scene", "rotor-pair", "-rotor_gap", 0], ["-rotor_gap", "'0'", "1e-6 to 1e4"]),
    ("rotor_gap 1e-300", ["-scene", "rotor-pair", "-rotor_gap", 1e-300], ["-rotor_gap", "'1e-300'", "1e-6 to 1e4"]),
    ("rotor_gap 1e300", ["-scene", "rotor-pair", "-rotor_gap", 1e300], ["-rotor_gap", "'1e+300'", "1e-6 to 1e4"]),
]
# List options with an empty element: PETSc's parser skips it ("-box_lo 1,,2" read as 1,2).
cases += [
    ("-box_lo 1,,2", file_scene + ["-box_lo", "1,,2", "-file_path", good], ["-box_lo", "'1,,2'", "element 2 is empty"]),
    ("-box_len 8,8,", file_scene[:-1] + ["8,8,", "-file_path", good], ["-box_len", "'8,8,'", "element 3 is empty"]),
    ("-periodic ,1", file_scene + ["-periodic", ",1", "-file_path", good], ["-periodic", "element 1 is empty"]),
    ("-scene_translate 1,,", ["-scene_translate", "1,,"], ["-scene_translate", "element 2 is empty"]),
    ("-gravity 0,,-1", ["-gravity", "0,,-1"], ["-gravity", "element 2 is empty"]),
    ("-arkode_adapt_params 0.5,,0.1,0.2", ["-arkode_adapt_params", "0.5,,0.1,0.2"], ["-arkode_adapt_params", "element 2 is empty"]),
]
# Options files PETSc would abort on (a traceback, exit 55 or 62): a line whose option name
# PETSc cannot read, more distinct options than its table holds (512), more aliases (25).
many = write("many.opts", "".join(f"-zz_option{i} 1\n" for i in range(520)))
cases += [
    ("options file line '--'", ["-options_file", write("dd.opts", "-expansion_n 4\n--\n")], ["dd.opts:2", "'--'", "not an option name"]),
    ("options file line '-1 2'", ["-options_file", write("num.opts", "-1 2\n")], ["num.opts:1", "not an option name"]),
    ("options file line '-inf'", ["-options_file", write("inf.opts", "-inf\n")], ["inf.opts:1", "not an option name"]),
    ("options file starting '---' (read as YAML)", ["-options_file", write("yaml.opts", "---\n-h 3\n")], ["yaml.opts:1", "not an option name"]),
    ("520 distinct options", ["-options_file", many], ["many.opts:511", "more than 510 distinct options"]),
    ("26 aliases", ["-options_file", write("alias.opts", "".join(f"alias -a{i} -h\n" for i in range(26)))], ["alias.opts:26", "more than 25 aliases"]),
]
for k, (name, args, needles) in enumerate(cases):
    out = os.path.join(w, f"out{k}")
    try:  # a FIFO must not block: well under the test's own timeout
        code, stdout, err = runner.run(args, out, timeout=20)
    except subprocess.TimeoutExpired:
        code, stdout, err = "timeout after 20 s", "", ""
    lines = err.strip().splitlines()
    # At most ~80 bytes of a user's line are echoed: no message runs to kilobytes.
    ok = (code == 2 and len(lines) == 1 and lines[0].startswith("spam-ark: error: ") and len(lines[0]) < 600
          and all(n in lines[0] for n in needles) and not os.path.exists(out))
    c.check(ok, f"{name}: exit {code}, stderr {[ln[:300] for ln in lines]}, output dir {'absent' if not os.path.exists(out) else 'PRESENT'}")

# Out of memory (it was a 19-line PETSc traceback): one line and exit 1, by
# the error handler, wherever the allocation failed. An address-space limit makes it fail
# within a second (the 2.25M-particle scene needs more); not under ASan, whose shadow memory
# alone is terabytes of address space.
if "ASAN_OPTIONS" not in os.environ:
    import resource
    # 2 GiB (the size first reported): the scene is built and the failure comes in the first
    # snapshot's gather, inside the output agreement that raises it again on every rank.
    # The other SUNDIALS integrators at 2 GiB: CVODE's Adams history and ARKStep's IMEX
    # vectors with its Krylov basis fail when their memory is asked for, before SUNDIALS
    # clones a vector it would use unchecked.
    tg = ["-scene", "taylor-green", "-taylorgreen_n", "1000", "-material", "gas", "-gas_e0", "0.5", "-viscosity_shear", "0.1"]
    oom_cases = [(limit, ["-expansion_n", "1500"]) for limit in (300_000_000, 800_000_000, 2 ** 31)]
    oom_cases += [(2 ** 31, ["-expansion_n", "1500", "-ts_type", "cvode"]), (2 ** 31, tg + ["-ts_type", "arkode_imex"])]
    for k, (limit, scene) in enumerate(oom_cases):
        out = os.path.join(w, f"oom{k}")
        p = subprocess.run([a.spam_ark] + scene + ["-ts_max_steps", "1", "-output_dir", out], capture_output=True, text=True, timeout=120,
                           preexec_fn=lambda n=limit: resource.setrlimit(resource.RLIMIT_AS, (n, n)))
        lines = p.stderr.strip().splitlines()
        s = json.load(open(os.path.join(out, "summary.json"))) if os.path.exists(os.path.join(out, "summary.json")) else {}
        c.check(p.returncode == 1 and len(lines) == 1 and lines[0].startswith("spam-ark: error: out of memory")
                and (not s or s["reason"].startswith("out of memory") and s["reason"].count("out of memory") == 1),
                f"out of memory under a {limit / 1e6:.0f} MB address space ({' '.join(scene[-2:])}): exit {p.returncode}, stderr {[ln[:200] for ln in lines[:3]]} ({len(lines)} lines), summary {s.get('reason', 'not written')!r}")

# PETSc reads ./.petscrc by itself (unless -skip_petscrc): the same check as -options_file.
rc_dir = os.path.join(w, "petscrc")
os.makedirs(rc_dir)
write(os.path.join("petscrc", ".petscrc"), "-h 3\n--\n")
for extra, want in ([], 2), (["-skip_petscrc"], 0):
    code, _, err = runner.run(["-expansion_n", "4", "-ts_max_time", "0.1", "-output_dir", "out"] + extra, timeout=120, cwd=rc_dir)
    lines = err.strip().splitlines()
    ok = code == want and (len(lines) == 1 and ".petscrc:2" in lines[0] and not os.path.exists(os.path.join(rc_dir, "out")) if want else not lines)
    c.check(ok, f"./.petscrc holding a line '--'{' with -skip_petscrc (not read)' if extra else ''}: exit {code} (want {want}), stderr {[ln[:200] for ln in lines[:3]]}")
    shutil.rmtree(os.path.join(rc_dir, "out"), ignore_errors=True)

# An options file missing on 2 ranks: said once, not once per rank.
if shutil.which("mpiexec"):
    mpiexec, env = mpiexec_env()
    p = subprocess.run([mpiexec, "--oversubscribe", "-n", "2", a.spam_ark, "-options_file", os.path.join(w, "missing.opts"), "-output_dir", os.path.join(w, "np2")],
                       capture_output=True, text=True, env=env, timeout=120)
    lines = [ln for ln in p.stderr.splitlines() if ln.startswith("spam-ark:")]
    c.check(p.returncode == 2 and len(lines) == 1 and "missing.opts" in lines[0] and not os.path.exists(os.path.join(w, "np2")),
            f"-options_file missing.opts on 2 ranks: exit {p.returncode}, spam-ark lines {lines}")
else:
    print("mpiexec not found: the two-rank case skipped")

# What the reader must still accept: CRLF line ends, a header with trailing spaces, a
# comment, a blank line, no end on the last line, a value that underflows to zero.
ok_file = write("crlf.csv", "x,y,vx,vy   \r\n# comment\r\n\r\n" + "".join(f"{i + 0.5},{j + 0.5},{1e-400 if i == 0 else 0},0\r\n" for j in range(8) for i in range(8)).rstrip("\r\n"))
out = os.path.join(w, "crlf_out")
code, stdout, err = runner.run(file_scene + ["-file_path", ok_file, "-ts_max_time", 0.1], out, timeout=120)
c.check(code == 0 and "64 particles" in stdout, f"CRLF, trailing header spaces, comment, blank line, no final newline, underflow: accepted (exit {code}, {err.strip()[:200]})")

# A particle with v = 1e308 and a step of 2 overflows its position at the DP stage
# c = 0.8 of step 1 (t = 1.6): a clean stop.
blow = write("blow.csv", "x,y,vx,vy\n" + "".join(f"{i + 0.5},{j + 0.5},{1e308 if (i, j) == (3, 4) else 0.0!r},0\n" for j in range(8) for i in range(8)))
out = os.path.join(w, "unstable")
code, stdout, err = runner.run(file_scene + ["-file_path", blow, "-arkode_fixed_step", 2, "-ts_max_time", 10], out)
with open(os.path.join(out, "summary.json")) as f:
    s = json.load(f)
c.check(code == 3, f"overflowing run exits with code 3 (got {code}), not a signal")
c.check(s["status"] == "unstable" and "particle 35" in s["reason"] and "t = 1.6" in s["reason"] and "step 1" in s["reason"], f"summary names the particle and time: {s['reason']}")
c.check("unstable" in stdout and "particle 35" in stdout, "the monitor says why it stopped")
c.check(os.path.exists(os.path.join(out, "particles_last_good.csv")), "the last good state is kept as a snapshot")
c.finish()
