"""The peer, LAMMPS: its table of Lucy's kernel, data and input files, running it, reading its
log, and the checks of that pipeline (--validate-lammps)."""

import re
from pathlib import Path

from bench_common import DT, _FLOAT, lucy_force, lucy_w, np, numpy_lattice, run_measured, tail


def write_table(path, h, npts, rlo, scale=1.0):
    """Write a LAMMPS pair_style table file (keyword SPAM) and check it.

    Columns: index r E F with E = scale*w(r), F = -dE/dr, r evenly spaced from
    rlo to h (declared with `N npts R rlo h`).  Returns finite-difference
    checks of F against E.
    """
    r = np.linspace(rlo, h, npts)
    e = scale * lucy_w(r, h)
    f = scale * lucy_force(r, h)
    with open(path, "w") as fh:
        fh.write("# Lucy 2D kernel as a pair potential, E = %.17g * w(r), "
                 "F = -dE/dr, h = %.17g\n\n" % (scale, h))
        fh.write("SPAM\nN %d R %.17g %.17g\n\n" % (npts, rlo, h))
        for i in range(npts):
            fh.write("%d %.17g %.17g %.17g\n" % (i + 1, r[i], e[i], f[i]))
    # (1) analytic F against a central difference of the analytic E.
    rr = np.linspace(rlo + 1e-3 * h, h * (1 - 1e-3), 4001)
    d = 1e-6 * h
    fd = -(scale * lucy_w(rr + d, h) - scale * lucy_w(rr - d, h)) / (2 * d)
    fa = scale * lucy_force(rr, h)
    fmax = float(np.max(np.abs(fa)))
    err_analytic = float(np.max(np.abs(fd - fa)) / fmax)
    # (2) the tabulated F column against a central difference of the
    #     tabulated E column (what LAMMPS itself interpolates).
    fd_tab = -(e[2:] - e[:-2]) / (r[2:] - r[:-2])
    err_table = float(np.max(np.abs(fd_tab - f[1:-1])) / fmax)
    return {"max_rel_err_F_vs_fd_analytic": err_analytic,
            "max_rel_err_F_vs_fd_table_columns": err_table,
            "F_max": fmax, "npts": npts, "rlo": rlo, "rhi": h}


def write_lammps_data(path, pos, vel, box, mass):
    n = len(pos)
    with open(path, "w") as fh:
        fh.write("spam-ark bench particles\n\n%d atoms\n1 atom types\n\n" % n)
        fh.write("0 %.17g xlo xhi\n0 %.17g ylo yhi\n-0.5 0.5 zlo zhi\n\n"
                 % (box[0], box[1]))
        fh.write("Masses\n\n1 %.17g\n\nAtoms # atomic\n\n" % mass)
        fh.writelines("%d 1 %.17g %.17g 0\n" % (i + 1, pos[i, 0], pos[i, 1])
                      for i in range(n))
        fh.write("\nVelocities\n\n")
        fh.writelines("%d %.17g %.17g 0\n" % (i + 1, vel[i, 0], vel[i, 1])
                      for i in range(n))


def lammps_input(data, table, h, skin, steps, table_n, dt=DT,
                 thermo_every=0, census=False, after_run=""):
    lines = [
        "units lj",
        "dimension 2",
        "atom_style atomic",
        "boundary p p p",
        "read_data %s" % data,
        "pair_style table linear %d" % table_n,
        "pair_coeff 1 1 %s SPAM %.17g" % (table, h),
        "neighbor %.17g bin" % skin,
        "neigh_modify every 1 delay 0 check yes",
        "fix 1 all nve",
        "fix 2 all enforce2d",
        "timestep %.17g" % dt,
    ]
    if census:
        lines += [
            "compute cn all coord/atom cutoff %.17g" % h,
            "compute cs all reduce sum c_cn",
            "thermo_style custom step c_cs pe ke etotal",
        ]
    else:
        lines.append("thermo_style custom step pe ke etotal")
    lines += [
        "thermo_modify norm no",
        "thermo %d" % thermo_every,
    ]
    lines.append("run %d" % steps)
    if after_run:
        lines.append(after_run)
    return "\n".join(lines) + "\n"


def parse_lammps_log(text):
    out = {}
    m = re.search(r"Loop time of (%s) on (\d+) procs for (\d+) steps with (\d+) atoms"
                  % _FLOAT, text)
    if m:
        out["loop_time_s"] = float(m.group(1))
        out["procs"] = int(m.group(2))
        out["steps"] = int(m.group(3))
        out["atoms"] = int(m.group(4))
    for sec in ("Pair", "Neigh", "Comm", "Output", "Modify"):
        m = re.search(r"^%s\s*\|\s*(%s)\s*\|\s*(%s)\s*\|\s*(%s)"
                      % (sec, _FLOAT, _FLOAT, _FLOAT), text, re.M)
        if m:
            out["%s_time_s" % sec.lower()] = float(m.group(2))  # avg column
    m = re.search(r"Neighbor list builds = (\d+)", text)
    if m:
        out["neighbor_builds"] = int(m.group(1))
    m = re.search(r"Dangerous builds = (\d+)", text)
    if m:
        out["dangerous_builds"] = int(m.group(1))
    m = re.search(r"Total # of neighbors = (\d+)", text)
    if m:
        out["total_neighbors_end"] = int(m.group(1))
    m = re.search(r"Per MPI rank memory allocation \(min/avg/max\) = (%s) \| (%s) \| (%s) Mbytes"
                  % (_FLOAT, _FLOAT, _FLOAT), text)
    if m:
        out["lammps_memory_mbytes"] = float(m.group(3))
    out["thermo"] = parse_thermo(text)
    m = re.search(r"^(ERROR.*)$", text, re.M)
    if m:
        out["error"] = m.group(1)
    out["warnings"] = sorted(set(re.findall(r"^WARNING: (.*)$", text, re.M)))
    return out


def parse_thermo(text):
    """Rows of the (last) thermo block: list of dicts keyed by column name."""
    rows = []
    lines = text.splitlines()
    for k, line in enumerate(lines):
        if line.split()[:1] == ["Step"]:
            cols = line.split()
            rows = []
            for l2 in lines[k + 1:]:
                parts = l2.split()
                if len(parts) != len(cols):
                    break
                try:
                    rows.append(dict(zip(cols, map(float, parts))))
                except ValueError:
                    break
    return rows


def lammps_run(lmp, data, table, h, skin, steps, table_n, workdir, tag, pin,
               thermo_every=0, census=False):
    inp = workdir / ("in_%s.lmp" % tag)
    inp.write_text(lammps_input(data.name, table.name, h, skin, steps, table_n,
                                thermo_every=thermo_every, census=census))
    log = workdir / ("lammps_%s.log" % tag)
    cmd = pin + [lmp, "-in", inp.name, "-log", "none", "-nocite"]
    rc, wall, rss = run_measured(cmd, workdir, log)
    res = parse_lammps_log(Path(log).read_text(errors="replace"))
    if rc != 0 or "loop_time_s" not in res:
        raise RuntimeError("LAMMPS run failed (rc=%d):\n  %s\n%s"
                           % (rc, " ".join(map(str, cmd)), tail(log)))
    res.update({"rc": rc, "process_wall_s": wall, "ru_maxrss_bytes": rss,
                "cmd": " ".join(map(str, cmd))})
    return res


def validate_lammps(args, workdir, pin, h=3.0):
    """Check the table/potential pipeline and energy conservation in LAMMPS."""
    report = {}
    table = workdir / "val_table.dat"
    report["table_check"] = write_table(table, h, args.table_points, args.table_rlo)
    print("table: max |F - FD(E)|/max F: analytic %.2e, table columns %.2e"
          % (report["table_check"]["max_rel_err_F_vs_fd_analytic"],
             report["table_check"]["max_rel_err_F_vs_fd_table_columns"]))

    # Forces and energy on a perturbed lattice against a direct numpy sum.
    rng = np.random.default_rng(12345)
    nx = 16
    box = np.array([2.0 * nx, 2.0 * nx])
    pos, vel, _ = numpy_lattice(nx)
    pos = pos + rng.uniform(-0.3, 0.3, pos.shape)
    vel = rng.normal(0.0, 0.1, pos.shape)
    data = workdir / "val_forces.data"
    write_lammps_data(data, pos, vel, box, 1.0)
    inp = workdir / "in_val_forces.lmp"
    inp.write_text(lammps_input(
        data.name, table.name, h, args.skin, 0, args.table_points,
        after_run="write_dump all custom val_forces.dump id x y fx fy "
                  "modify sort id format float %.17g"))
    log = workdir / "lammps_val_forces.log"
    rc, _, _ = run_measured(pin + [args.lmp, "-in", inp.name, "-log", "none", "-nocite"],
                            workdir, log)
    if rc != 0:
        raise RuntimeError("LAMMPS force check failed:\n" + tail(log))
    dump = np.loadtxt(workdir / "val_forces.dump", skiprows=9)
    f_lmp = dump[:, 3:5]
    n = len(pos)
    d = pos[:, None, :] - pos[None, :, :]
    d -= box * np.round(d / box)
    r = np.sqrt(np.einsum("ijk,ijk->ij", d, d))
    np.fill_diagonal(r, np.inf)
    fr = lucy_force(r, h)
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = np.where(np.isfinite(r)[..., None], d / r[..., None], 0.0)
    f_np = np.sum(fr[..., None] * unit, axis=1)
    pe_np = 0.5 * float(np.sum(lucy_w(np.where(np.isfinite(r), r, 10 * h), h)))
    pe_lmp = parse_thermo(log.read_text())[0]["PotEng"]
    ferr = float(np.max(np.abs(f_lmp - f_np)) / np.max(np.abs(f_np)))
    report["force_check"] = {"n": n, "max_rel_force_err": ferr,
                             "pe_lammps": pe_lmp, "pe_numpy": pe_np,
                             "pe_rel_err": abs(pe_lmp - pe_np) / abs(pe_np)}
    print("forces on a perturbed %d-particle lattice: max |F_lammps - F_numpy|/max|F| = %.2e;"
          " pair energy %.10g (LAMMPS) vs %.10g (numpy), rel err %.2e"
          % (n, ferr, pe_lmp, pe_np, report["force_check"]["pe_rel_err"]))

    # Energy conservation for the expansion itself on a small lattice.
    nx = 32
    box = np.array([2.0 * nx, 2.0 * nx])
    pos, vel, _ = numpy_lattice(nx)
    data = workdir / "val_drift.data"
    write_lammps_data(data, pos, vel, box, 1.0)
    report["energy_drift"] = []
    for dt, steps in ((DT, 400), (DT / 2, 800)):
        inp = workdir / "in_val_drift.lmp"
        inp.write_text(lammps_input(data.name, table.name, h, args.skin, steps,
                                    args.table_points, dt=dt,
                                    thermo_every=max(1, steps // 40)))
        log = workdir / "lammps_val_drift.log"
        rc, _, _ = run_measured(pin + [args.lmp, "-in", inp.name, "-log", "none",
                                       "-nocite"], workdir, log)
        if rc != 0:
            raise RuntimeError("LAMMPS drift check failed:\n" + tail(log))
        rows = parse_thermo(log.read_text())
        e = np.array([row["TotEng"] for row in rows])
        ke = np.array([row["KinEng"] for row in rows])
        rec = {"dt": dt, "steps": steps, "t_end": dt * steps, "n": len(pos),
               "E0": float(e[0]), "E_end": float(e[-1]),
               "rel_drift_end": float((e[-1] - e[0]) / abs(e[0])),
               "max_rel_dev": float(np.max(np.abs(e - e[0])) / abs(e[0])),
               "ke_end_over_E0": float(ke[-1] / abs(e[0]))}
        report["energy_drift"].append(rec)
        print("energy, %d particles, dt %.4g, %d steps (t=%.4g): E0 %.8g, E_end %.8g, "
              "rel drift %.2e, max rel deviation %.2e (KE reaches %.0f%% of E0)"
              % (len(pos), dt, steps, dt * steps, rec["E0"], rec["E_end"],
                 rec["rel_drift_end"], rec["max_rel_dev"], 100 * rec["ke_end_over_E0"]))
    return report
