"""Centreline velocities of the lid-driven cavity from

    U. Ghia, K. N. Ghia and C. T. Shin, "High-Re solutions for incompressible flow using the
    Navier-Stokes equations and a multigrid method", J. Comput. Phys. 48 (1982) 387-411,
    Table I (u along the vertical line through the geometric centre, x = 0.5) and
    Table II (v along the horizontal line through the geometric centre, y = 0.5),

for Re = 100 and 1000, in the paper's units: the cavity is the unit square, the lid (y = 1)
moves at u = 1, and the points are those of its 129 x 129 grid (the paper's point numbers
are kept in the comments). Every number was checked against two independent public
transcriptions of the tables (a PeleLMeX cavity post-processing script and a Python
benchmark module of a SIMPLE solver); a third transcription seen had typing slips (-0.2 for
-0.21090, -0.020581 for -0.20581), which is why each number was compared. (Table II at
Re = 400, x = 0.9063, not carried here, reads -0.23827 in some copies and -0.33827 in others.)

The lists run from the lower wall to the upper (Table I) and from the left wall to the right
(Table II); the first and last entries are the walls' own velocities."""

# Table I: y (grid point 1, 8, 9, 10, 14, 23, 37, 59, 65, 80, 95, 110, 123, 124, 125, 126, 129)
U_Y = (0.0000, 0.0547, 0.0625, 0.0703, 0.1016, 0.1719, 0.2813, 0.4531, 0.5000,
       0.6172, 0.7344, 0.8516, 0.9531, 0.9609, 0.9688, 0.9766, 1.0000)
U = {
    100: (0.00000, -0.03717, -0.04192, -0.04775, -0.06434, -0.10150, -0.15662, -0.21090, -0.20581,
          -0.13641, 0.00332, 0.23151, 0.68717, 0.73722, 0.78871, 0.84123, 1.00000),
    1000: (0.00000, -0.18109, -0.20196, -0.22220, -0.29730, -0.38289, -0.27805, -0.10648, -0.06080,
           0.05702, 0.18719, 0.33304, 0.46604, 0.51117, 0.57492, 0.65928, 1.00000),
}

# Table II: x (grid point 1, 9, 10, 11, 13, 21, 30, 31, 65, 104, 111, 117, 122, 123, 124, 125, 129)
V_X = (0.0000, 0.0625, 0.0703, 0.0781, 0.0938, 0.1563, 0.2266, 0.2344, 0.5000,
       0.8047, 0.8594, 0.9063, 0.9453, 0.9531, 0.9609, 0.9688, 1.0000)
V = {
    100: (0.00000, 0.09233, 0.10091, 0.10890, 0.12317, 0.16077, 0.17507, 0.17527, 0.05454,
          -0.24533, -0.22445, -0.16914, -0.10313, -0.08864, -0.07391, -0.05906, 0.00000),
    1000: (0.00000, 0.27485, 0.29012, 0.30353, 0.32627, 0.37095, 0.33075, 0.32235, 0.02526,
           -0.31966, -0.42665, -0.51550, -0.39188, -0.33714, -0.27669, -0.21388, 0.00000),
}


def extrema(re):
    """Ghia's extrema on the centrelines at this Re: min u on x = 0.5, max and min v on
    y = 0.5 (the tabulated points' own extrema)."""
    return {"u_min": min(U[re]), "v_max": max(V[re]), "v_min": min(V[re])}
