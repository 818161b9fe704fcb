"""The lid-driven cavity (scene cavity): centreline profiles of a particle snapshot against
Ghia, Ghia & Shin (1982), shared by tests/run_cavity.py and examples/plot_cavity.py.

A profile value at a point P is the kernel-weighted (Shepard) average of the velocities of
the particles within h of P, their mirror images in the no-slip walls included: an image of
particle i in a wall moving at v_w sits at the mirrored position with velocity 2 v_w - v_i,
as the run's own images do (docs/walls.md), so the average near a wall is that of the
velocity field SPAM sees there rather than one biased towards the interior. Lengths are in
units of the side L, velocities in units of the lid speed U, as Ghia's tables are."""
import math
import ghia1982


def read_particles(path):
    """(x, y, vx, vy) of every particle of a particle CSV (the -final_csv / -initial_csv /
    snapshot format: a header line with the column names, then one row per particle)."""
    with open(path) as f:
        lines = [ln for ln in f if ln.strip() and not ln.startswith("#")]
    names = lines[0].strip().split(",")
    k = [names.index(c) for c in ("x", "y", "vx", "vy")]
    out = []
    for ln in lines[1:]:
        v = ln.split(",")
        out.append(tuple(float(v[j]) for j in k))
    return out


def with_images(parts, L, U, h):
    """The particles and their no-slip images in the four walls of [0, L]^2 (the lid y = L
    moving at (U, 0)), for every particle within h of a wall; a corner image (within h of
    two walls) applies both mirrors in turn, as the run does."""
    out = list(parts)
    for x, y, vx, vy in parts:
        xs = [(x, 0.0)] + [(-x, 0.0)] * (x < h) + [(2 * L - x, 0.0)] * (L - x < h)
        ys = [(y, 0.0)] + [(-y, 0.0)] * (y < h) + [(2 * L - y, U)] * (L - y < h)
        for k, (xi, _) in enumerate(xs):
            for j, (yi, wall_u) in enumerate(ys):
                if k == 0 and j == 0:
                    continue
                ux, uy = vx, vy
                if k:  # mirrored in a side wall at rest
                    ux, uy = -ux, -uy
                if j:  # mirrored in the floor (at rest) or the lid (moving at U along x)
                    ux, uy = 2 * wall_u - ux, -uy
                out.append((xi, yi, ux, uy))
    return out


def wendland_c2(q):
    """The 2D Wendland C2 kernel's shape at q = r/h (its normalisation cancels)."""
    return (1 - q) ** 4 * (1 + 4 * q) if q < 1 else 0.0


def shepard(parts, px, py, h):
    """Kernel-weighted mean (vx, vy) of parts within h of (px, py); None if there is none."""
    sw = su = sv = 0.0
    for x, y, vx, vy in parts:
        r = math.hypot(x - px, y - py)
        if r < h:
            w = wendland_c2(r / h)
            sw += w
            su += w * vx
            sv += w * vy
    return (su / sw, sv / sw) if sw > 0 else None


def centrelines(parts, L, U, h, ys, xs):
    """u/U at (L/2, y L) for y in ys and v/U at (x L, L/2) for x in xs."""
    full = with_images(parts, L, U, h)
    u = [shepard(full, 0.5 * L, y * L, h)[0] / U for y in ys]
    v = [shepard(full, x * L, 0.5 * L, h)[1] / U for x in xs]
    return u, v


def snapshot_profiles(parts, L, U, h, fine=128):
    """One snapshot's centreline profiles: at Ghia's points (u at U_Y, v at V_X) and on the
    fine line (fine - 1 points, walls excluded). combine() averages such profiles; computing
    them once per snapshot lets a caller have both the mean over the snapshots and each
    snapshot's own errors (run_cavity's spread) without walking the particles twice."""
    line = [k / fine for k in range(1, fine)]
    u, v = centrelines(parts, L, U, h, ghia1982.U_Y, ghia1982.V_X)
    uf, vf = centrelines(parts, L, U, h, line, line)
    return dict(u=u, v=v, line=line, u_line=uf, v_line=vf)


def combine(profiles, re):
    """The mean of snapshot_profiles() results and its errors against Ghia at this Re (see
    compare)."""
    def mean(key):
        cols = [p[key] for p in profiles]
        return [sum(c) / len(cols) for c in zip(*cols)]

    u, v, uf, vf = mean("u"), mean("v"), mean("u_line"), mean("v_line")
    inner = range(1, len(ghia1982.U_Y) - 1)
    linf_u = max(abs(u[k] - ghia1982.U[re][k]) for k in inner)
    linf_v = max(abs(v[k] - ghia1982.V[re][k]) for k in inner)
    g = ghia1982.extrema(re)
    ext = {"u_min": min(uf), "v_max": max(vf), "v_min": min(vf)}
    rel = {k: (ext[k] - g[k]) / abs(g[k]) for k in ext}
    return dict(u=u, v=v, line=profiles[0]["line"], ghia_u_top=ghia1982.U[re][-2], u_line=uf, v_line=vf, linf_u=linf_u,
                linf_v=linf_v, extrema=ext, ghia_extrema=g, rel=rel, snapshots=len(profiles))


def compare(snapshots, L, U, h, re, fine=128):
    """The profiles at Ghia's points and their errors against Ghia at this Re, averaged
    over the snapshots (a list of particle lists; one particle list is one snapshot):
    linf_u, linf_v: the largest |SPAM - Ghia| (units of U) over Ghia's points off the walls
    (the walls' values are the boundary conditions); u_min, v_max, v_min: the extrema of
    the mean SPAM profiles on a fine line (fine + 1 points, walls excluded) and their
    relative errors (SPAM - Ghia) / |Ghia| against the extrema of Ghia's points. The mean
    over snapshots takes out the flow's own unsteadiness (the sound the lid keeps
    launching at Mach 0.1 moves a single snapshot's extrema by several per cent)."""
    if snapshots and isinstance(snapshots[0], tuple):
        snapshots = [snapshots]
    return combine([snapshot_profiles(parts, L, U, h, fine) for parts in snapshots], re)
