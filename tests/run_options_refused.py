#!/usr/bin/python3
"""Options as a whole: nonsense values, wrong array lengths,
missing values, options this run does not use, unknown options (with the nearest name),
bad options files. Each refusal: exit 2, exactly one stderr line starting
"spam-ark: error: " that holds the needles (the option, the value, what is allowed), and
no output directory. Then what must still run: every options file, PETSc's own run-time
options, -version, --version, --help and -help listing every option group."""
import glob
import os
import re

from spamrun import Checks, Runner, arguments

a = arguments()
c = Checks()
W = a.workdir
runner = Runner(a.spam_ark, W)  # each run a forked child of the fork server
REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FILE = ["-scene", "file", "-file_path", os.path.join(W, "p.csv"), "-box_len", "64,64"]
with open(os.path.join(W, "p.csv"), "w") as f:
    f.write("x,y,vx,vy\n10,10,0,0\n12,10,0,0\n")


def opts_file(name, text):
    path = os.path.join(W, name)
    with open(path, "wb") as f:
        f.write(text)
    return path


misspelled = opts_file("misspelled.opts", b"-h 3\n-ts_rtoll 1e-6\n")
bad_line = opts_file("bad_line.opts", b"# a comment\n-h 3\nfoo bar\n")
extra = opts_file("extra.opts", b"-h 3 4\n")
nul = opts_file("nul.opts", b"-h 3\n-mass\x001\n")
nested = opts_file("nested.opts", b"-options_file " + os.path.join(W, "missing.opts").encode() + b"\n")
fifo = os.path.join(W, "fifo.opts")
os.mkfifo(fifo)

cases = [
    # values
    ("max growth NaN", ["-arkode_max_growth", "nan"], ["-arkode_max_growth", "'nan'", "greater than 1"]),
    ("max growth negative", ["-arkode_max_growth", -2], ["-arkode_max_growth", "'-2'", "greater than 1"]),
    ("max growth inf", ["-arkode_max_growth", "inf"], ["-arkode_max_growth", "'inf'", "finite"]),
    ("max growth below 1 (ARKODE would ignore it)", ["-arkode_max_growth", 0.5], ["-arkode_max_growth", "'0.5'"]),
    ("max first growth NaN", ["-arkode_max_first_growth", "nan"], ["-arkode_max_first_growth", "'nan'"]),
    ("max efail growth above 1", ["-arkode_max_efail_growth", 2], ["-arkode_max_efail_growth", "'2'", "(0, 1]"]),
    ("max efail growth negative", ["-arkode_max_efail_growth", -1], ["-arkode_max_efail_growth", "'-1'"]),
    ("safety inf", ["-arkode_safety", "inf"], ["-arkode_safety", "'inf'", "between 0 and 1"]),
    ("safety negative", ["-arkode_safety", -0.5], ["-arkode_safety", "'-0.5'", "between 0 and 1"]),
    ("grid spacing NaN", ["-diag_grid_spacing", "nan"], ["-diag_grid_spacing", "'nan'"]),
    ("grid spacing negative", ["-diag_grid_spacing", -1], ["-diag_grid_spacing", "'-1'"]),
    ("grid spacing tiny", ["-diag_grid_spacing", "8.951e-05"], ["-diag_grid_spacing", "'8.951e-05'", "grid cells", "at most"]),
    ("negative max reject", ["-ts_max_reject", -1], ["-ts_max_reject", "'-1'", "at least 1"]),
    ("7 controller gains", ["-arkode_adapt_params", "1,2,3,4,5,6,7"], ["-arkode_adapt_params", "'1,2,3,4,5,6,7'", "exactly 3", "7 given"]),
    ("2 controller gains", ["-arkode_adapt_params", "0.5,0.5"], ["-arkode_adapt_params", "exactly 3"]),
    ("4 box corners", FILE + ["-box_lo", "1,2,3,4"], ["-box_lo", "'1,2,3,4'", "1 value", "or 2"]),
    ("4 box edges", FILE[:-2] + ["-box_len", "64,64,64,64"], ["-box_len", "'64,64,64,64'", "4 given"]),
    ("5 translations", ["-scene_translate", "1,2,3,4,5"], ["-scene_translate", "'1,2,3,4,5'", "5 given"]),
    ("3 periodic flags in 2D", FILE + ["-periodic", "1,0,1"], ["-periodic", "'1,0,1'", "3 given"]),
    ("box corner NaN", FILE + ["-box_lo", "nan"], ["-box_lo", "'nan'", "finite"]),
    ("box corner inf", FILE + ["-box_lo", "inf"], ["-box_lo", "'inf'", "finite"]),
    ("box edge NaN", FILE[:-2] + ["-box_len", "64,nan"], ["-box_len", "'64,nan'", "finite"]),
    ("box edge not a number", FILE[:-2] + ["-box_len", "64,abc"], ["-box_len", "'64,abc'", "must be a number"]),
    ("translation NaN", ["-scene_translate", "nan"], ["-scene_translate", "'nan'", "finite"]),
    ("translation huge", ["-scene_translate", "1e20"], ["-scene_translate", "'1e20'"]),
    ("h 1e-300", ["-h", "1e-300"], ["-h", "'1e-300'", "normal finite"]),
    ("h 1e300", ["-h", "1e300"], ["-h", "'1e300'", "normal finite"]),
    ("h tiny for the box", ["-h", "1e-3"], ["-h", "'1e-3'", "cells", "at most"]),
    ("end time 1e-300", ["-ts_max_time", "1e-300"], ["-ts_max_time", "'1e-300'", "too small"]),
    ("output interval 1e-300", ["-output_interval", "1e-300"], ["-output_interval", "'1e-300'", "rows", "at most 1000000"]),
    ("output interval past 10^6 rows", ["-output_interval", "1e-5"], ["-output_interval", "'1e-5'", "rows"]),
    ("snapshot interval past -snapshot_max", ["-snapshot_interval", "0.001"], ["-snapshot_interval", "'0.001'", "snapshots", "-snapshot_max = 10000"]),
    ("CFL fraction 1e-300", ["-step_cfl", "1e-300"], ["-step_cfl", "'1e-300'", "too small"]),
    ("fixed step below the floor", ["-arkode_fixed_step", "1e-20"], ["-arkode_fixed_step", "'1e-20'", "step floor"]),
    ("TS fixed step below the floor", ["-ts_type", "euler", "-ts_dt", "1e-20"], ["-ts_dt", "'1e-20'", "step floor"]),
    ("gamma 0 named as gamma", ["-eos_gamma", 0], ["-eos_gamma", "'0'", "greater than 1"]),
    ("subnormal mass: too small", ["-mass", "1e-310"], ["-mass", "'1e-310'", "too small"]),
    ("subnormal tolerance: too small", ["-ts_rtol", "1e-310"], ["-ts_rtol", "'1e-310'", "too small"]),
    ("dimension not an integer", ["-dim", "2.5"], ["-dim", "'2.5'", "integer"]),
    ("boolean not a boolean", ["-monitor", "maybe"], ["-monitor", "'maybe'", "true or false"]),
    ("value with a space", ["-h", "3 4"], ["-h", "'3 4'", "must be a number"]),
    ("integer with a space", ["-expansion_n", "8 9"], ["-expansion_n", "'8 9'", "integer"]),
    # options present without a value
    ("-h without a value", ["-h"], ["-h", "missing value"]),
    ("-ts_rtol without a value", ["-ts_rtol", "-monitor"], ["-ts_rtol", "missing"]),
    ("empty string value", ["-arkode_adapt", ""], ["-arkode_adapt", "missing or empty"]),
    ("translation without a value", ["-scene_translate"], ["-scene_translate", "missing"]),
    ("-expansion_n without a value", ["-expansion_n", "-h", 3], ["-expansion_n", "missing"]),
    # options this run does not use
    ("arkode table under rk", ["-ts_type", "rk", "-arkode_table", "ARKODE_VERNER_8_5_6"],
     ["-arkode_table", "'ARKODE_VERNER_8_5_6'", "not used", "applies to -ts_type arkode", "-ts_type rk"]),
    ("arkode safety under cvode", ["-ts_type", "cvode", "-arkode_safety", 0.9], ["-arkode_safety", "'0.9'", "-ts_type arkode", "cvode"]),
    ("cvode order under arkode", ["-cvode_max_order", 3], ["-cvode_max_order", "'3'", "-ts_type cvode"]),
    ("rtol under Verlet", ["-ts_type", "basicsymplectic", "-ts_rtol", "1e-6"], ["-ts_rtol", "'1e-6'", "adaptive", "basicsymplectic"]),
    ("atol under fixed-step rk 4", ["-ts_type", "rk", "-ts_rk_type", 4, "-ts_adapt_type", "none", "-ts_atol", "1e-9"],
     ["-ts_atol", "'1e-9'", "adaptive", "rk"]),
    ("rtol under a fixed ERKStep step", ["-arkode_fixed_step", 0.1, "-ts_rtol", "1e-6"], ["-ts_rtol", "adaptive", "-arkode_fixed_step"]),
    ("controller under a fixed ERKStep step", ["-arkode_fixed_step", 0.1, "-arkode_adapt", "pi"], ["-arkode_adapt", "'pi'", "adaptive"]),
    ("ts_dt beside a fixed ERKStep step", ["-arkode_fixed_step", 0.1, "-ts_dt", 0.2], ["-ts_dt", "'0.2'", "-arkode_fixed_step"]),
    ("PETSc adaptor type unknown under arkode", ["-ts_adapt_type", "3"], ["-ts_adapt_type", "'3'", "none, basic, dsp"]),
    ("PETSc adaptor bound out of range", ["-ts_type", "rk", "-ts_adapt_dt_max", "1e-310"], ["-ts_* option", "1e-310"]),
    ("PETSc adaptor option under arkode", ["-ts_adapt_dt_max", 3], ["-ts_adapt_dt_max", "'3'", "adaptor"]),
    ("rk scheme under ssp", ["-ts_type", "ssp", "-ts_rk_type", "5dp"], ["-ts_rk_type", "'5dp'", "-ts_type rk"]),
    ("box of the file scene under expansion", ["-periodic", 0, "-box_len", "100,100"], ["-box_len", "'100,100'", "-scene file", "expansion"]),
    ("periodic flags under rotor", ["-scene", "rotor", "-periodic", 0], ["-periodic", "'0'", "-scene expansion and file", "rotor"]),
    ("gas exponent on the chain", ["-scene", "chain", "-dim", 1, "-eos_gamma", 2], ["-eos_gamma", "'2'", "-material isentrope", "chain"]),
    ("solid option on the isentrope", ["-viscosity", "monaghan"], ["-viscosity", "'monaghan'", "-material gas and elastic", "isentrope"]),
    ("gas energy of an elastic solid", ["-scene", "rotor", "-gas_e0", 2], ["-gas_e0", "'2'", "-material gas"]),
    ("XSPH epsilon under R0", ["-scene", "rotor", "-xsph_eps", 0.5], ["-xsph_eps", "'0.5'", "-coordinates R2", "R0"]),
    ("gas scheme of an elastic solid", ["-scene", "rotor", "-gas_scheme", "flow"], ["-gas_scheme", "'flow'", "-material gas", "elastic"]),
    ("shift under the plain gas scheme", ["-scene", "taylor-green", "-material", "gas", "-viscosity_shear", 1, "-gas_scheme", "plain",
                                         "-shift_coefficient", 0.2], ["-shift_coefficient", "'0.2'", "-gas_scheme flow", "plain"]),
    ("background of an inviscid gas", ["-scene", "sod", "-background_pressure", "none"],
     ["-background_pressure", "'none'", "-gas_scheme flow", "plain"]),
    ("viscosity gains without viscosity", ["-scene", "tensile", "-viscosity_alpha", 2], ["-viscosity_alpha", "'2'", "monaghan"]),
    ("torque scope without torque scaling", ["-scene", "rotor", "-angmom_scope", "body"], ["-angmom_scope", "'body'", "Ti and Tij"]),
    ("initial density under summation", ["-scene", "rotor", "-density", "summation", "-density_initial", "summed"],
     ["-density_initial", "'summed'", "continuity"]),
    ("lattice of another scene", ["-scene", "rotor", "-tensile_nx", 30], ["-tensile_nx", "'30'", "-scene tensile", "rotor"]),
    ("expansion lattice in the rotor", ["-scene", "rotor", "-expansion_n", 8], ["-expansion_n", "'8'", "-scene expansion"]),
    ("grid spacing without entropy", ["-diag_entropy", 0, "-diag_grid_spacing", 2], ["-diag_grid_spacing", "'2'", "-diag_entropy"]),
    ("misspelled option", ["-ts_rtoll", "1e-6"], ["unknown option -ts_rtoll", "'1e-6'", "did you mean -ts_rtol?"]),
    ("misspelled arkode table", ["-arkode_tabel", "ARKODE_VERNER_8_5_6"], ["-arkode_tabel", "did you mean -arkode_table?"]),
    ("option with '='", ["-ts_rtol=1e-8"], ["-ts_rtol=1e-8", "space, not '='", "-ts_rtol 1e-8"]),
    ("unknown option far from any", ["-frobnicate", 1], ["unknown option -frobnicate", "-help"]),
    # PETSc reads the solvers' options for every TS type (and marks them used); no method
    # here creates a solver, so they are refused like any option the run does not use.
    ("a Krylov solver's option", ["-ksp_type", "gmres"], ["-ksp_type", "not used", "implicit solvers"]),
    ("a preconditioner's option", ["-pc_type", "jacobi"], ["-pc_type", "not used", "implicit solvers"]),
    ("a nonlinear solver's option", ["-snes_type", "newtonls"], ["-snes_type", "not used", "implicit solvers"]),
    ("misspelled option in an options file", ["-options_file", misspelled], ["unknown option -ts_rtoll", "did you mean -ts_rtol?"]),
    # options files
    ("missing options file", ["-options_file", os.path.join(W, "missing.opts")], ["-options_file", "missing.opts", "cannot open"]),
    ("options file is a directory", ["-options_file", W], ["-options_file", "directory"]),
    ("options file is a FIFO", ["-options_file", fifo], ["-options_file", "not a regular file"]),
    ("options file without a name", ["-options_file"], ["-options_file", "needs a file name"]),
    ("line not starting with '-'", ["-options_file", bad_line], ["bad_line.opts:3", "'foo bar'"]),
    ("two values on a line", ["-options_file", extra], ["extra.opts:1", "'-h 3 4'", "at most one value"]),
    ("NUL byte in an options file", ["-options_file", nul], ["nul.opts:2", "NUL"]),
    ("nested options file missing", ["-options_file", nested], ["-options_file", "missing.opts", "cannot open"]),
    # the adaptive kernel range: its options, and what it does not take yet
    ("adaptive range on the isentrope", ["-scene", "expansion", "-smoothing_length", "adaptive"], ["-smoothing_length", "not used", "isentrope"]),
    ("h_eta at the fixed range", ["-scene", "sedov", "-h_eta", "3"], ["-h_eta", "smoothing_length adaptive", "fixed"]),
    ("unknown kernel range", ["-scene", "sedov", "-smoothing_length", "wide"], ["-smoothing_length", "'wide'", "fixed, adaptive"]),
    ("h_max below 1", ["-scene", "sedov", "-smoothing_length", "adaptive", "-h_max", "0.5"], ["-h_max", "'0.5'", "from 1 to 10"]),
    ("adaptive range with continuity", ["-scene", "sedov", "-smoothing_length", "adaptive", "-density", "continuity"], ["-smoothing_length", "'adaptive'", "-density continuity"]),
    ("adaptive range with walls", ["-scene", "sedov", "-smoothing_length", "adaptive", "-wall_xlo", "freeslip"], ["-smoothing_length", "'adaptive'", "mirror walls"]),
    ("adaptive range with ghost images", ["-scene", "sedov", "-smoothing_length", "adaptive", "-periodic_images", "ghost"], ["-smoothing_length", "'adaptive'", "-periodic_images ghost"]),
    ("adaptive range with grid fields", ["-scene", "sedov", "-smoothing_length", "adaptive", "-grid_interval", "1"], ["-smoothing_length", "'adaptive'", "-grid_interval"]),
]
for k, (name, args, needles) in enumerate(cases):
    out = os.path.join(W, f"out{k}")
    code, _, err = runner.run(args + (["-ts_max_steps", 1] if "-options_file" not in args else []), out, timeout=60)
    lines = err.strip().splitlines()
    ok = (code == 2 and len(lines) == 1 and lines[0].startswith("spam-ark: error: ")
          and all(n in lines[0] for n in needles) and not os.path.exists(out))
    c.check(ok, f"{name}: exit {code}, stderr {lines}")

# Bytes outside printable ASCII are escaped, so the message stays one line.
out = os.path.join(W, "escaped")
code, _, err = runner.run(["-scene", "ab\x01c\x7f\xe9"], out)
lines = err.strip().splitlines()
c.check(code == 2 and len(lines) == 1 and "ab\\x01c\\x7f\\xc3\\xa9" in lines[0] and not re.search(r"[\x00-\x1f\x7f]", lines[0]),
        f"control bytes escaped as \\xNN: exit {code}, stderr {lines}")

# A system failure is one line and exit 1, no traceback.
code, _, err = runner.run(["-ts_max_steps", 1], "/proc/spam-ark-test/out")
lines = err.strip().splitlines()
c.check(code == 1 and len(lines) == 1 and lines[0].startswith("spam-ark: error: ") and "/proc/spam-ark-test" in lines[0],
        f"unwritable output path: exit {code}, stderr {lines}")

# What still runs: every options file (three steps), booleans alone, PETSc's run-time options.
for name in sorted(os.listdir(os.path.join(REPO, "options"))):
    out = os.path.join(W, "opts_" + name)
    code, _, err = runner.run(["-options_file", os.path.join(REPO, "options", name), "-ts_max_steps", 3], out)
    c.check(code == 0 and os.path.exists(os.path.join(out, "summary.json")) and "error" not in err,
            f"options/{name} runs: exit {code}, stderr {err.strip().splitlines()[-1:]}")
for extra in (["-monitor"], ["-log_view"], ["-malloc_debug"], ["-options_left"], ["-ts_monitor"],
              ["-ts_type", "rk", "-ts_adapt_dt_max", 2], ["-scene", "rotor", "-coordinates", "R2", "-xsph_eps", 0.5],
              ["-scene_translate", "-5,-5"], ["-scene_translate", -7]):
    out = os.path.join(W, "ok_" + "_".join(str(x).strip("-") for x in extra))
    code, _, err = runner.run(extra + ["-ts_max_steps", 2], out)
    c.check(code == 0 and "error" not in err, f"{' '.join(map(str, extra))} runs: exit {code}, stderr {err.strip().splitlines()[-1:]}")
# A preset of an options file overridden on the command line: a note, not a refusal.
out = os.path.join(W, "preset")
code, _, err = runner.run(["-options_file", os.path.join(REPO, "options", "planewave.opts"), "-ts_type", "euler", "-ts_max_steps", 2], out)
c.check(code == 0 and "spam-ark: note: -ts_rtol = '1e-10' (from an options file): not used" in err,
        f"planewave.opts under euler: exit {code}, notes {[l for l in err.splitlines() if 'note' in l]}")

# -version, --version, --help, -help.
version = re.search(r'SPAM_VERSION "([^"]+)"', open(os.path.join(REPO, "include", "spam", "version.h")).read()).group(1)
for flag in ("-version", "--version"):
    code, out, err = runner.run([flag])
    c.check(code == 0 and out.strip() == f"spam-ark {version}" and not err, f"{flag}: exit {code}, stdout {out.strip()!r}")
for flag in ("-help", "--help"):
    code, out, err = runner.run([flag])
    want = ["-arkode_table", "-cvode_max_order", "-box_len", "-periodic", "-eos_gamma", "-expansion_n", "-tensile_nx",
            "-rotor_gap", "-chain_n", "-spring_range", "-planewave_mode", "-xsph_eps", "-gas_e0", "-solid_lambda",
            "-viscosity_alpha", "-angmom_scope", "-density_initial", "-diag_grid_spacing", "-gas_scheme",
            "-background_pressure", "-shift_coefficient"]
    missing = [w for w in want if not re.search(r"^\s+" + re.escape(w) + r"  .*\[default ", out, re.M)]
    c.check(code == 0 and not missing and not os.path.exists("out_help_should_not_exist"), f"{flag}: exit {code}, missing {missing}")
# -help is for spam-ark's users: its own options and time stepping with plain defaults, none
# of PETSc's solver, viewer or device blocks (-help petsc prints those, in PETSc's words).
for extra in ([], ["-ts_type", "rk"], ["-ts_type", "cvode"], ["-scene", "convection"]):
    code, out, _ = runner.run(extra + ["-help"])
    lines = out.splitlines()
    petsc_words = [l for l in lines if "<now " in l or "(README)" in l or "-snes_" in l or "-ksp_" in l or "-pc_" in l]
    c.check(code == 0 and len(lines) <= 400 and not petsc_words,
            f"-help {' '.join(extra)}: {len(lines)} lines (at most 400), {len(petsc_words)} in PETSc's form or of solvers "
            f"({petsc_words[:2]})")
# The file scene lists its options without a particle file: -help needs no input, and the
# set-up after the scene (model, outputs, time stepping) lists its options too.
for extra in ([], ["-dim", "3"], ["-box_len", "64,32"]):
    code, out, err = runner.run(["-scene", "file"] + extra + ["-help"])
    missing = [w for w in ("-file_path", "-box_len", "-material", "-output_dir", "-ts_rtol", "-cvode_max_order")
               if not re.search(r"^\s+" + re.escape(w) + r"  .*\[default ", out, re.M)]
    c.check(code == 0 and not missing and "error" not in err,
            f"-scene file {' '.join(extra)} -help without -file_path: exit {code}, missing {missing} {err.strip()[:200]}")
code, full, _ = runner.run(["-help", "petsc"])
c.check(code == 0 and "-snes_type" in full and "-ksp_type" in full and "(README)" in full,
        f"-help petsc: exit {code}, PETSc's whole text ({len(full.splitlines())} lines)")
# Every option of spam-ark in -help is known to the check of unused options, which decides
# where it applies and whether it takes a value: from its table (src/integrate/option_use.c)
# or, for a scene's own option, from that scene's table (src/scenes/scene_*.c). PETSc's form
# of -help (-help petsc) marks them with "(README)".
out = full
listed = set(re.findall(r"^\s+-([a-z0-9_]+) <.*\(README\)$", out, re.M))
known = set(re.findall(r'\{"([a-z0-9_]+)", PETSC_(?:TRUE|FALSE), G_', open(os.path.join(REPO, "src", "integrate", "option_use.c")).read()))
for method in glob.glob(os.path.join(REPO, "src", "integrate", "ts_*.c")):  # the TS types' own options
    known |= set(re.findall(r'\{"([a-z0-9_]+)", PETSC_(?:TRUE|FALSE), PETSC_(?:TRUE|FALSE)\}', open(method).read()))
for scene in glob.glob(os.path.join(REPO, "src", "scenes", "scene_*.c")):
    known |= set(re.findall(r'\{"([a-z0-9_]+)", SPAM_SCENE_OPTION_[A-Z]+,', open(scene).read()))
c.check(len(listed) > 60 and not listed - known, f"{len(listed)} options in -help, all in the table of option_use.c or a scene's (missing: {sorted(listed - known)})")
c.finish()
