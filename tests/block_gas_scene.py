"""The small scene of the block-step tests (run_block_order.py, run_block_error.py): 16 x 16
particles of the ideal gas (gamma 1.4, unit lattice, periodic, h = 3, summation density,
Monaghan's viscosity), e = 1 + 20 exp(-r^2/4) about an off-centre point and random
velocities (deviation 0.1, fixed seed), to T = 1."""
import numpy as np

N, E_HOT, T = 16, 20.0, 1.0


def write_gas(path):
    rng = np.random.default_rng(1)
    with open(path, "w") as f:
        f.write("x,y,vx,vy,m,e\n")
        for j in range(N):
            for i in range(N):
                x, y = i + 0.5, j + 0.5
                e = 1.0 + E_HOT * np.exp(-((x - 5.3) ** 2 + (y - 6.1) ** 2) / 4.0)
                vx, vy = 0.1 * rng.standard_normal(2)
                f.write(f"{x!r},{y!r},{vx!r},{vy!r},1,{e!r}\n")


def scene(gas, output_interval=0):
    """The options of the scene read from gas (written by write_gas)."""
    return ["-scene", "file", "-file_path", gas, "-dim", 2, "-box_lo", "0,0", "-box_len", f"{N},{N}", "-periodic", "true,true", "-h", 3,
            "-material", "gas", "-gas_gamma", 1.4, "-density", "summation", "-viscosity", "monaghan", "-ts_max_time", T,
            "-output_interval", output_interval]
