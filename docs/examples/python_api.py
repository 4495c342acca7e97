from harness.fmu.blade import BladeFMU

# 0.3 s at 5000 rpm, load amplitude F_w0 = 100 N/m (engine order 3), gap d = 0.04 mm;
# BladeFMU builds build/ShroudedBlade.fmu when it is missing or out of date.
with BladeFMU() as fmu:
    out = fmu.run({"Fw0": 100.0, "d": 4e-5}, stop_time=0.3, step=1e-4, speed=5000.0)

last = out[out["time"] > 0.25]                            # the last 50 ms
print(f"{len(out)} rows: {', '.join(out.dtype.names[:4])}, ...")
print(f"amplitude over the last 50 ms: {abs(last['tipDisplacement']).max():.4e} m")
