#!/usr/bin/python3
"""One particle file format, read and written.

A CSV header names its columns in any order (x y z vx vy vz m e rho sxx sxy syy sxz syz szz
id, and the snapshots' rho_sum); a header-less file is the legacy x,y,vx,vy layout. What the
run writes (-initial_csv, -final_csv, CSV and HDF5 snapshots) reads back unchanged. A column
the model cannot hold, an unknown or duplicate column or a missing position is bad input: one
line, exit 2. Unequal masses are read and written back per particle."""
import json
import math
import os
import random
import shutil
import subprocess
from spamrun import Checks, arguments, run

a = arguments()
c = Checks()
w = a.workdir
FAST = ["-monitor", 0, "-diag_entropy", 0]


def write(name, text):
    path = os.path.join(w, name)
    with open(path, "w") as f:
        f.write(text)
    return path


def rows(path):
    """Data rows of a particles CSV as {column: text}, comments skipped."""
    with open(path) as f:
        lines = [ln.rstrip("\n") for ln in f if ln.strip() and not ln.startswith("#")]
    head = lines[0].split(",")
    return [dict(zip(head, ln.split(","))) for ln in lines[1:]]


def read_back(name, path, extra=()):
    """Reads a particle file as a file scene, runs no step, and returns the state it read
    (written by -initial_csv) or the error line."""
    out = os.path.join(w, name)
    csv = out + ".csv"
    code, _, err = run(a.spam_ark, ["-scene", "file", "-file_path", path, "-ts_max_time", 0, "-initial_csv", csv] + FAST + list(extra), out)
    return code, (rows(csv) if code == 0 else []), err.strip()


# A 4 x 4 lattice in the box 8 x 8 with distinct velocities, shuffled once.
rng = random.Random(7)
lattice = [(2 * i + 1.0, 2 * j + 1.0, round(rng.uniform(-0.1, 0.1), 6), round(rng.uniform(-0.1, 0.1), 6)) for j in range(4) for i in range(4)]
box = ["-box_len", "8,8", "-h", 3]


def as_csv(header, fields):
    """The lattice in the given header, each row's values picked by fields(k, particle)."""
    return header + "\n" + "".join(",".join(str(v) for v in fields(k, p)) + "\n" for k, p in enumerate(lattice))


def same_state(got, vel=True):
    """Positions and velocities as read equal the lattice (bitwise: %.17g of the decimal)."""
    return len(got) == len(lattice) and all(
        float(r["x"]) == p[0] and float(r["y"]) == p[1] and (not vel or (float(r["vx"]) == p[2] and float(r["vy"]) == p[3]))
        for r, p in zip(got, lattice))


# --- header permutations -----------------------------------------------------------------
order = list(range(len(lattice)))
rng.shuffle(order)
perms = [
    ("x,y,vx,vy", "x,y,vx,vy", lambda k, p: p, True),
    ("vy,vx,y,x", "reversed", lambda k, p: (p[3], p[2], p[1], p[0]), True),
    ("y,vy,x,vx,m", "interleaved with m", lambda k, p: (p[1], p[3], p[0], p[2], 1), True),
    (" x , y ", "positions only, spaces around names", lambda k, p: (p[0], p[1]), False),
]
for n, (header, name, fields, vel) in enumerate(perms):
    code, got, err = read_back(f"perm{n}", write(f"perm{n}.csv", as_csv(header, fields)), box)
    rest = all(float(r["vx"]) == 0 and float(r["vy"]) == 0 for r in got)
    c.check(code == 0 and same_state(got, vel) and (vel or rest), f"header {header!r} ({name}): {len(got)} particles read as written{'' if vel else ', at rest'} {err[:160]}")
legacy = write("legacy.csv", "".join(f"{p[0]},{p[1]},{p[2]},{p[3]}\n" for p in lattice))
code, got, err = read_back("legacy", legacy, box)
c.check(code == 0 and same_state(got), f"header-less legacy file read as x,y,vx,vy ({len(got)} particles) {err[:160]}")
# ids: the particle of id k is row k of every output.
shuffled = [lattice[order[k]] for k in range(len(lattice))]
with open(os.path.join(w, "ids.csv"), "w") as f:
    f.write("id,vx,x,vy,y\n" + "".join(f"{order[k]},{p[2]},{p[0]},{p[3]},{p[1]}\n" for k, p in enumerate(shuffled)))
code, got, err = read_back("ids", os.path.join(w, "ids.csv"), box)
c.check(code == 0 and same_state(got) and [int(r["id"]) for r in got] == list(range(len(lattice))),
        f"id column: {len(got)} shuffled rows come back in id order, ids 0..{len(lattice) - 1} {err[:160]}")

# --- every column --------------------------------------------------------------------------
code, got, err = read_back("mass", write("mass.csv", as_csv("x,y,vx,vy,m", lambda k, p: p + (0.75,))), box)
c.check(code == 0 and got and all(float(r["m"]) == 0.75 for r in got), f"column m, equal masses 0.75: accepted, written back as m = 0.75 {err[:160]}")
code, _, err = read_back("mass_option", os.path.join(w, "mass.csv"), box + ["-mass", 1])
c.check(code == 2 and err.count("\n") == 0 and "-mass" in err and "column m" in err, f"-mass other than the file's masses refused: {err[:160]}")
code, got, err = read_back("mass_option_same", os.path.join(w, "mass.csv"), box + ["-mass", 0.75])
c.check(code == 0 and len(got) == 16, f"-mass equal to the file's masses accepted {err[:160]}")
code, got, err = read_back("unequal", write("unequal.csv", as_csv("x,y,vx,vy,m", lambda k, p: p + (1 + (k == 5),))), box)
c.check(code == 0 and [float(r["m"]) for r in got] == [1.0 + (k == 5) for k in range(len(lattice))],
        f"unequal masses accepted and written back per particle (m = 2 for particle 6): {err[:200]}")
for header, extra, column in [("x,y,e", (0.5,), "'e'"), ("x,y,rho", (1.1,), "'rho'"), ("x,y,sxx,sxy,syy", (0.1, 0.0, 0.1), "stress")]:
    code, got, err = read_back("col_" + header[4:7], write(f"col{header[4:7]}.csv", as_csv(header, lambda k, p: p[:2] + extra)), box)
    c.check(code == 2 and err.count("\n") == 0 and column in err and "x y vx vy" in err,
            f"column {header[4:]} refused by the isentrope, naming the column and the model's state: {err[:200]}")
code, got, err = read_back("rho_sum", write("rho_sum.csv", as_csv("x,y,vx,vy,rho_sum", lambda k, p: p + (0.3,))), box)
c.check(code == 0 and same_state(got), f"rho_sum (a snapshot's summed density) accepted, not read {err[:160]}")
cube = "x,y,z,vx,vy,vz,m,id\n" + "".join(f"{2 * i + 1},{2 * j + 1},{2 * k + 1},0.01,0,-0.01,1,{i + 4 * j + 16 * k}\n" for k in range(4) for j in range(4) for i in range(4))
code, got, err = read_back("cube", write("cube.csv", cube), ["-dim", 3, "-box_len", 8, "-h", 3])
c.check(code == 0 and len(got) == 64 and all(float(r["vz"]) == -0.01 for r in got) and float(got[17]["z"]) == 3.0,
        f"3D file with every kinematic column and ids: {len(got)} particles {err[:160]}")

# --- bad headers: one line, exit 2 -------------------------------------------------------------
bad = [("unknown column", "x,y,vx,vy,q", "unknown column 'q'"), ("duplicate column", "x,y,vx,x", "column x appears twice"),
       ("missing x", "y,vx,vy", "no column x"), ("z in 2D", "x,y,z", "column z needs -dim 3"),
       ("part of the stress", "x,y,sxx,syy", "all of its 3 components"), ("empty name", "x,,y", "has no name")]
for name, header, want in bad:
    code, _, err = read_back("bad", write("bad.csv", header + "\n1,1,0,0\n"), box)
    c.check(code == 2 and err.count("\n") == 0 and "bad.csv:1" in err and want in err, f"{name} ({header}): {err[:160]}")
code, _, err = read_back("badid", write("badid.csv", "x,y,id\n1,1,0\n3,3,0\n"), box)
c.check(code == 2 and err.count("\n") == 0 and "earlier particle" in err, f"duplicate id refused: {err[:160]}")
code, _, err = read_back("badid2", write("badid2.csv", "x,y,id\n1,1,0\n3,3,1.5\n"), box)
c.check(code == 2 and "badid2.csv:3" in err and "whole number" in err, f"fractional id refused naming file:line: {err[:160]}")

# --- what a run writes reads back --------------------------------------------------------------
# Fixed steps, so the straight and the continued run take the same steps; the restart
# rebuilds the neighbour list (whose pair order sets the round-off) at t = 1.
gas = ["-scene", "expansion", "-expansion_n", 8, "-h", 3, "-arkode_fixed_step", 0.01] + FAST
straight = os.path.join(w, "straight.csv")
code1, _, err1 = run(a.spam_ark, gas + ["-ts_max_time", 2, "-final_csv", straight], os.path.join(w, "straight"))
mid = os.path.join(w, "mid.csv")
code2, _, err2 = run(a.spam_ark, gas + ["-ts_max_time", 1, "-final_csv", mid, "-snapshot_interval", 1, "-snapshot_csv"], os.path.join(w, "first"))
cont = os.path.join(w, "cont.csv")
code3, _, err3 = run(a.spam_ark, ["-scene", "file", "-file_path", mid, "-box_len", 16, "-h", 3, "-arkode_fixed_step", 0.01,
                                  "-ts_max_time", 1, "-sort_particles", 0, "-final_csv", cont] + FAST, os.path.join(w, "second"))
if c.check(code1 == code2 == code3 == 0, f"straight run 0..2, first half 0..1, continued 1..2 from -final_csv: exits {code1} {code2} {code3} {(err1 + err2 + err3)[:200]}"):
    s, t = rows(straight), rows(cont)
    dx = max(abs(math.remainder(float(p[k]) - float(q[k]), 16.0)) for p, q in zip(s, t) for k in ("x", "y"))
    dv = max(abs(float(p[k]) - float(q[k])) for p, q in zip(s, t) for k in ("vx", "vy"))
    vmax = max(abs(float(p[k])) for p in s for k in ("vx", "vy"))
    # Not bitwise: the restart rebuilds the neighbour list at t = 1, and its pair order sets
    # the round-off of the sums (1e-16 relative). Bound: that round-off grown over 100 steps
    # of one time unit, 1e-13, far below the step's own local error
    # (dt^5 = 1e-10): the continued run is the straight run, not a nearby one.
    c.check(len(s) == len(t) == 64 and dx < 1e-13 and dv < 1e-13 * max(vmax, 1.0),
            f"continued run equals the straight run: max |dx| {dx:.2e}, max |dv| {dv:.2e} (bound 1e-13; |v| up to {vmax:.3f})")
    c.reading("continued.dx", dx)
    c.reading("continued.dv", dv)
    code, got, err = read_back("mid_again", mid, ["-box_len", 16])
    c.check(code == 0 and [tuple(r.values()) for r in got] == [tuple(r.values()) for r in rows(mid)],
            f"-final_csv read back and written again is the same text ({len(got)} rows) {err[:160]}")
    snapcsv = os.path.join(w, "first", "particles_00001.csv")
    code, got, err = read_back("snapcsv", snapcsv, ["-box_len", 16])
    same = code == 0 and all(r[k] == q[k] for r, q in zip(got, rows(snapcsv)) for k in ("x", "y", "vx", "vy", "m", "id"))
    c.check(same and len(got) == 64, f"CSV snapshot (time comment, rho_sum) read back unchanged {err[:160]}")

# HDF5 snapshot read back as a file scene: bitwise the positions and velocities it holds
# (compared with the CSV snapshot of the same state, printed with %.17g).
h5 = os.path.join(w, "first", "snap_00001.h5")
code, got, err = read_back("h5", h5)
snap = rows(os.path.join(w, "first", "particles_00001.csv")) if os.path.exists(h5) else []
c.check(code == 0 and len(got) == 64 and all(r[k] == q[k] for r, q in zip(got, snap) for k in ("x", "y", "vx", "vy", "m", "id")),
        f"HDF5 snapshot read back: {len(got)} particles, positions and velocities bitwise, box from its attributes {err[:160]}")
with open(os.path.join(w, "renamed.csv"), "wb") as f, open(h5, "rb") as g:
    f.write(g.read())
code, got2, err = read_back("h5_renamed", os.path.join(w, "renamed.csv"))
c.check(code == 0 and got2 == got, f"an HDF5 snapshot named .csv is read as HDF5 (by its signature) {err[:160]}")
code, _, err = read_back("h5_box", h5, ["-box_len", 15])
c.check(code == 2 and err.count("\n") == 0 and "has box_len 16" in err, f"-box_len other than the snapshot's refused: {err[:160]}")
code, _, err = read_back("h5_box_same", h5, ["-box_len", 16, "-periodic", 1])
c.check(code == 0, f"-box_len and -periodic equal to the snapshot's accepted {err[:160]}")
code, _, err = read_back("h5_dim", h5, ["-dim", 3])
c.check(code == 2 and "add -dim 2" in err, f"-dim other than the snapshot's refused: {err[:160]}")


def restamp(path):
    """Stamps a snapshot's checksum again, as a forger who knows the format would: its first
    512 bytes are the line "spam-ark snapshot; FNV-1a 64 of the bytes from 512 on: HASH"
    padded with NULs (written out here from the format, not from the program's code), so
    that what the reader refuses below is the forged value, not the checksum."""
    with open(path, "r+b") as f:
        data = f.read()
        h = 0xcbf29ce484222325
        for b in data[512:]:
            h = ((h ^ b) * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
        block = f"spam-ark snapshot; FNV-1a 64 of the bytes from 512 on: {h:016x}\n".encode().ljust(512, b"\0")
        f.seek(0)
        f.write(block)
    return True


def h5_set(path, obj, name, values, attribute=True):
    """Rewrites a snapshot in place through libhdf5 (ctypes; h5py is not installed):
    attribute name of obj replaced by float64 values, or (attribute=False) dataset
    obj/name overwritten with values, then its checksum stamped again (restamp). True when
    every call succeeded."""
    import ctypes
    h5 = ctypes.CDLL("libhdf5_openmpi.so.103")
    hid = ctypes.c_int64
    for f in ("H5Fopen", "H5Oopen", "H5Screate_simple", "H5Acreate2", "H5Dopen2"):
        getattr(h5, f).restype = hid
    h5.H5open()
    dbl = hid.in_dll(h5, "H5T_NATIVE_DOUBLE_g").value
    buf = (ctypes.c_double * len(values))(*values)
    f = h5.H5Fopen(path.encode(), ctypes.c_uint(1), hid(0))  # H5F_ACC_RDWR, H5P_DEFAULT
    ok = f >= 0
    if attribute:
        o = h5.H5Oopen(hid(f), obj.encode(), hid(0))
        h5.H5Adelete(hid(o), name.encode())
        space = h5.H5Screate_simple(1, (ctypes.c_uint64 * 1)(len(values)), None)
        at = h5.H5Acreate2(hid(o), name.encode(), hid(dbl), hid(space), hid(0), hid(0))
        ok = ok and o >= 0 and at >= 0 and h5.H5Awrite(hid(at), hid(dbl), buf) >= 0
        h5.H5Aclose(hid(at)), h5.H5Sclose(hid(space)), h5.H5Oclose(hid(o))
    else:
        d = h5.H5Dopen2(hid(f), (obj + name).encode(), hid(0))
        ok = ok and d >= 0 and h5.H5Dwrite(hid(d), hid(dbl), hid(0), hid(0), hid(0), buf) >= 0  # H5S_ALL
        h5.H5Dclose(hid(d))
    return ok and h5.H5Fclose(hid(f)) >= 0 and restamp(path)


# Values a snapshot holds as integers or positive normal numbers, forged: refused in one
# line, nothing written (before: dim = 2.7 was read as 2, a subnormal mass ran).
forged = [("dim 2.7", "/", "dim", [2.7], True, "attribute dim is not a whole number"),
          ("periodic 1,0.5", "/", "periodic", [1.0, 0.5], True, "attribute periodic holds a value that is not a whole number"),
          ("carried 0.5", "/density", "carried", [0.5], True, "attribute carried of /density is not a whole number"),
          ("subnormal mass", "/", "mass", [1.0] * 63 + [4.9e-324], False, "particle 64: mass 4.9406564584124654e-324: too small (subnormal)")]
for k, (name, obj, attr, values, attribute, want) in enumerate(forged):
    bad = os.path.join(w, f"forged{k}.h5")
    made = os.path.exists(h5) and shutil.copyfile(h5, bad) and h5_set(bad, obj, attr, values, attribute)
    code, _, err = read_back(f"forged{k}", bad)
    c.check(made and code == 2 and err.count("\n") == 0 and want in err and not os.path.exists(os.path.join(w, f"forged{k}")),
            f"snapshot with {name}: refused in one line, nothing written (forged {made}, exit {code}): {err[:200]}")
made = os.path.exists(h5) and shutil.copyfile(h5, os.path.join(w, "whole.h5")) and h5_set(os.path.join(w, "whole.h5"), "/", "dim", [2.0])
code, got, err = read_back("whole", os.path.join(w, "whole.h5"))
c.check(made and code == 0 and len(got) == 64, f"snapshot with dim stored as the float 2.0: a whole number, read (exit {code}) {err[:160]}")
if shutil.which("h5dump"):
    dump = subprocess.run(["h5dump", "-A", h5], capture_output=True, text=True).stdout
    names = ("time", "step", "dim", "box_lo", "box_len", "periodic", "kernel_h", "units", "units_convention", "version", "model")
    missing = [n for n in names if f'ATTRIBUTE "{n}"' not in dump]
    model = dump.split('ATTRIBUTE "model"')[1].split("(0): ", 1)[1].split("\n")[0].strip() if not missing else '""'
    settings = json.loads(model[1:-1])  # h5dump quotes the string without escaping it
    c.check(not missing and settings.get("model") == "isentrope" and settings.get("h") == 3 and settings.get("eos_gamma") == 2,
            f"snapshot attributes {', '.join(names)} present (missing {missing}); model {settings}")
    sets = {ln.split()[0] for ln in subprocess.run(["h5ls", h5], capture_output=True, text=True).stdout.splitlines() if ln.strip()}
    c.check({"mass", "id", "positions", "velocities", "density"} <= sets, f"snapshot datasets {sorted(sets)} include mass and id")
else:
    c.check(False, "h5dump (hdf5-tools) is installed")
c.finish(a.readings)
