"""The ring of harness/system/ring.py in libcosim (libcosimpy): the same FMUs, one-to-one
connections, libcosim's fixed-step algorithm (all slaves step, then outputs go to inputs; inputs
held, no derivatives).

Connections: blade j -> contact j side A and blade j+1 -> contact j side B (tipDisplacement ->
displacement*, tipVelocity -> velocity*); contact j forceA -> blade j contactForce2, contact j forceB
-> blade j+1 contactForce (libcosim cannot add two outputs into one input: the blade adds its two
force inputs). Built-in load: every blade gets Fw0, bladeIndex, bladeCount, engineOrder, and blades
and contacts rotorSpeed as the inputs' initial value (constant speed).
After a step the contact's outputs are those at the end of its step (u moved along the held
velocities, harness/system/ring.py docs), so the blades get the force of the extrapolated u.
"""

from __future__ import annotations

import time

import numpy as np

from harness.fmu.libcosim import last_error, samples
from harness.system.time_grid import to_ns
from harness.fmu.slave import variables_by_name
from harness.fmu.slave import build_ring_fmus
from harness.optional import require
from harness.system.ring import Ring


def run(ring: Ring) -> dict[str, np.ndarray]:
    """time [s] and per blade q, v; per contact forceA, forceB, at libcosim's communication points;
    step_wall: the wall time [s] of libcosim's stepping (loading and initialization left out)."""
    require("libcosimpy")
    # optional dependency (extra `crosscheck`): imported only when this runs
    from libcosimpy.CosimEnums import CosimVariableType
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.ERROR)
    bx, sc = build_ring_fmus()
    N, K = ring.n, ring.n_steps
    ex = CosimExecution.from_step_size(step_size=to_ns(ring.step))
    speed = {"rotorSpeed": float(ring.speed)}  # the inputs' initial value
    params = {
        "blade": (bx, None),
        "contact": (sc, {**dict(ring.contact), "engineOrder": ring.engine_order, **speed}),
    }
    var = {p: variables_by_name(p) for p, _ in params.values()}
    idx: dict[tuple[str, int], int] = {}
    keep = []
    for kind, (path, p) in params.items():
        for i in range(N):
            sl = CosimLocalSlave(fmu_path=str(path), instance_name=f"{kind}{i}")
            keep.append(sl)
            k = ex.add_local_slave(local_slave=sl)
            if k < 0:
                raise RuntimeError(f"libcosim could not load {path}: {last_error()}")
            idx[kind, i] = k
            vals = {**ring.blade_instance_params(i), **speed} if kind == "blade" else p
            for name, v in vals.items():
                vr, typ = var[path][name]
                ok = {
                    "Real": lambda: ex.real_initial_value(k, vr, float(v)),
                    "Integer": lambda: ex.integer_initial_value(k, vr, int(v)),
                    "Boolean": lambda: ex.boolean_initial_value(k, vr, bool(v)),
                }[typ]()
                if not ok:
                    raise RuntimeError(f"libcosim refused {kind}{i}.{name} = {v}: {last_error()}")

    def connect(a: tuple[str, int], out: str, b: tuple[str, int], inp: str) -> None:
        pa, pb = params[a[0]][0], params[b[0]][0]
        if ex.connect_real_variables(idx[a], var[pa][out][0], idx[b], var[pb][inp][0]) != 0:
            raise RuntimeError(f"libcosim: cannot connect {a}.{out} -> {b}.{inp}: {last_error()}")

    for i in range(N):
        j = (i + 1) % N
        connect(("blade", i), "tipDisplacement", ("contact", i), "displacementA")
        connect(("blade", i), "tipVelocity", ("contact", i), "velocityA")
        connect(("blade", j), "tipDisplacement", ("contact", i), "displacementB")
        connect(("blade", j), "tipVelocity", ("contact", i), "velocityB")
        connect(("contact", i), "forceA", ("blade", i), "contactForce2")
        connect(("contact", i), "forceB", ("blade", j), "contactForce")
    obs = CosimObserver.create_time_series(buffer_size=K + 16)
    ex.add_observer(observer=obs)
    series = [
        ("blade", "q", "tipDisplacement"),
        ("blade", "v", "tipVelocity"),
        ("contact", "forceA", "forceA"),
        ("contact", "forceB", "forceB"),
    ]
    for kind, _, name in series:
        for i in range(N):
            if not obs.start_time_series(idx[kind, i], var[params[kind][0]][name][0], CosimVariableType.REAL):
                raise RuntimeError(f"libcosim cannot observe {kind}{i}.{name}: {last_error()}")
    t0 = time.perf_counter()
    if not ex.step(K):
        raise RuntimeError(f"libcosim failed: {last_error()}")
    step_wall = time.perf_counter() - t0
    res: dict[str, np.ndarray] = {}
    for kind, key, name in series:
        cols = []
        for i in range(N):
            t_ns, steps, vals = samples(obs, idx[kind, i], var[params[kind][0]][name][0], "Real", K + 1)
            cols.append(vals)
        res[key] = np.array(cols).T
    res["time"] = np.asarray(t_ns, dtype=np.int64) / 1e9
    res["step_wall"] = np.array(step_wall)  # wall time of the stepping alone (harness/bench.py)
    return res
