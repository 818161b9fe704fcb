#!/usr/bin/python3
"""Bad input to the elastic scenes, the harmonic chain and the tensor-path options (including an option of a
choice not made, e.g. -solid_lambda with -material gas): one line on stderr naming the option, the value and
what is allowed; exit code 2; no output directory."""
import os

from spamrun import Checks, Runner, arguments

a = arguments()
c = Checks()
runner = Runner(a.spam_ark, a.workdir)  # each run a forked child of the fork server
cases = [
    ("unknown density", ["-scene", "rotor", "-density", "sum"], ["-density", "'sum'", "summation, continuity, chain-rule"]),
    ("unknown coordinates", ["-scene", "rotor", "-coordinates", "R3"], ["-coordinates", "'R3'", "R0, R1, R2"]),
    ("unknown angmom", ["-scene", "rotor", "-angmom", "Tk"], ["-angmom", "'Tk'", "none, gauss, Ti, Tij"]),
    ("unknown scope", ["-scene", "rotor-pair", "-angmom_scope", "local"], ["-angmom_scope", "'local'", "global, body"]),
    ("unknown viscosity", ["-scene", "tensile", "-viscosity", "lucy"], ["-viscosity", "'lucy'", "monaghan"]),
    ("unknown material", ["-scene", "rotor", "-material", "steel"], ["-material", "'steel'", "elastic, gas"]),
    ("gas gamma 1", ["-scene", "rotor", "-material", "gas", "-gas_gamma", 1], ["-gas_gamma", "'1'", "greater than 1"]),
    ("negative conductivity", ["-scene", "rotor", "-conductivity", -1], ["-conductivity", "'-1'", "non-negative"]),
    ("unknown gas scheme", ["-scene", "taylor-green", "-material", "gas", "-gas_scheme", "tvf"], ["-gas_scheme", "'tvf'", "plain, flow"]),
    ("unknown background", ["-scene", "taylor-green", "-material", "gas", "-viscosity_shear", 1, "-background_pressure", "min"],
     ["-background_pressure", "'min'", "none, mean"]),
    ("negative shift", ["-scene", "taylor-green", "-material", "gas", "-viscosity_shear", 1, "-shift_coefficient", -0.1],
     ["-shift_coefficient", "'-0.1'", "non-negative"]),
    ("linear conduction without the pair form", ["-scene", "taylor-green", "-material", "gas", "-viscosity_shear", 1, "-conductivity", 1,
                                                 "-diffusion_form", "gradient", "-conduction_linear"], ["-conduction_linear", "'true'", "-diffusion_form pair"]),
    ("linear conduction without conduction", ["-scene", "taylor-green", "-material", "gas", "-viscosity_shear", 1,
                                              "-conduction_linear"], ["-conduction_linear", "'true'", "-conductivity > 0"]),
    ("linear conduction without the flow laws", ["-scene", "taylor-green", "-material", "gas", "-viscosity_shear", 1, "-conductivity", 1,
                                                 "-background_pressure", "none", "-shift_coefficient", 0, "-conduction_linear"],
     ["-conduction_linear", "'true'", "-background_pressure mean"]),
    ("shift compression without the shift", ["-scene", "taylor-green", "-material", "gas", "-viscosity_shear", 1, "-shift_coefficient", 0,
                                             "-shift_compression"], ["-shift_compression", "'true'", "-shift_coefficient > 0"]),
    ("shift compression with a continuity density", ["-scene", "taylor-green", "-material", "gas", "-viscosity_shear", 1, "-density", "continuity",
                                                     "-shift_compression"], ["-shift_compression", "'true'", "-density summation"]),
    ("shift beyond sound", ["-scene", "taylor-green", "-material", "gas", "-viscosity_shear", 1, "-shift_coefficient", 20],
     ["-shift_coefficient", "'20'", "0 <= C <= 10"]),
    ("zero shear modulus", ["-scene", "planewave", "-solid_eta", 0], ["-solid_eta", "'0'", "positive"]),
    ("odd rows", ["-scene", "planewave", "-planewave_ny", 23], ["-planewave_ny", "'23'", "even"]),
    ("unknown polarisation", ["-scene", "planewave", "-planewave_mode", "shear"], ["-planewave_mode", "'shear'", "transverse, longitudinal"]),
    ("amplitude too large", ["-scene", "planewave", "-planewave_amplitude", 0.6], ["-planewave_amplitude", "'0.6'", "< 0.5"]),
    ("unknown initial stress", ["-scene", "planewave", "-planewave_stress", "exact"], ["-planewave_stress", "'exact'", "spam, continuum"]),
    ("zero shells", ["-scene", "rotor", "-rotor_n", 0], ["-rotor_n", "'0'", "1 to 1000"]),
    ("negative speed", ["-scene", "rotor", "-rotor_speed", -0.1], ["-rotor_speed", "'-0.1'", "positive"]),
    ("spring range beyond h", ["-scene", "rotor-md", "-spring_range", 3.5], ["-spring_range", "'3.5'", "0 < range < h"]),
    ("tensile crystal narrower than 2h", ["-scene", "tensile", "-tensile_nx", 4], ["box edge x", "at least 2h"]),
    ("symplectic split of a state with stress", ["-scene", "planewave", "-ts_type", "basicsymplectic"],
     ["-ts_type", "'basicsymplectic'", "positions and velocities only", "sxx", "use rk"]),
    ("negative closest approach", ["-scene", "tensile", "-closest_approach", -0.5], ["-closest_approach", "'-0.5'", "non-negative"]),
    ("elastic scene in 3D", ["-scene", "rotor", "-dim", 3], ["-dim", "'3'", "two-dimensional"]),
    ("chain in 2D", ["-scene", "chain"], ["-dim", "'2'", "one-dimensional"]),
    ("odd chain", ["-scene", "chain", "-dim", 1, "-chain_n", 63], ["-chain_n", "'63'", "even"]),
    ("subnormal shear modulus: too small", ["-scene", "planewave", "-solid_eta", "1e-310"], ["-solid_eta", "'1e-310'", "too small"]),
    ("NaN viscosity coefficient", ["-scene", "tensile", "-viscosity", "monaghan", "-viscosity_alpha", "nan"],
     ["-viscosity_alpha", "'nan'", "finite"]),
    ("gas gamma NaN with conduction", ["-scene", "rotor", "-conductivity", 0.1, "-gas_gamma", "nan"], ["-gas_gamma", "'nan'", "greater than 1"]),
    ("Lame constant of a gas", ["-scene", "rotor", "-material", "gas", "-solid_lambda", 1], ["-solid_lambda", "'1'", "-material elastic"]),
    ("gas energy of an elastic solid", ["-scene", "tensile", "-gas_e0", 2], ["-gas_e0", "'2'", "-material gas"]),
    ("chain amplitude too large", ["-scene", "chain", "-dim", 1, "-chain_amplitude", 0.3], ["-chain_amplitude", "'0.3'", "< 0.25"]),
    # the smooth flows with exact answers
    ("gresho energy by -gas_e0", ["-scene", "gresho", "-gas_e0", 2], ["-gas_e0", "'2'", "-gresho_p0"]),
    ("gresho as an elastic solid", ["-scene", "gresho", "-material", "elastic"], ["-material", "'elastic'", "-material gas"]),
    ("gresho zero central pressure", ["-scene", "gresho", "-gresho_p0", 0], ["-gresho_p0", "'0'", "1e-100"]),
    ("taylor-green as the isentrope", ["-scene", "taylor-green", "-material", "isentrope"], ["-material", "'isentrope'", "-material gas"]),
    ("taylor-green infinite amplitude", ["-scene", "taylor-green", "-taylorgreen_amplitude", "inf"], ["-taylorgreen_amplitude", "'inf'", "finite"]),
    ("heat mode amplitude 1", ["-scene", "heat-mode", "-heatmode_eps", 1], ["-heatmode_eps", "'1'", "|eps| < 1"]),
    ("heat mode rows in 1D", ["-scene", "heat-mode", "-dim", 1, "-heatmode_ny", 12], ["-heatmode_ny", "'12'", "one-dimensional"]),
    ("heat mode option in another scene", ["-scene", "gresho", "-heatmode_n", 30], ["-heatmode_n", "'30'", "-scene heat-mode", "gresho"]),
]
for k, (name, args, needles) in enumerate(cases):
    out = os.path.join(a.workdir, f"out{k}")
    code, _, err = runner.run(args, out)
    lines = err.strip().splitlines()
    ok = (code == 2 and len(lines) == 1 and lines[0].startswith("spam-ark: error: ")
          and all(n in lines[0] for n in needles) and not os.path.exists(out))
    c.check(ok, f"{name}: exit {code}, stderr {lines}")
c.finish()
