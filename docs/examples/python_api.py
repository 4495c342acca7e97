import harness

# 0.3 s from rest at 5000 rpm, load amplitude Fw0 = 100 N/m (engine order 3), gap d = 0.04 mm;
# in a checkout the FMU is built into build/ when missing or out of date.
out = harness.simulate(0.3, speed_rpm=5000.0, step=1e-4, Fw0=100.0, d=4e-5)

last = out[out["time"] > 0.25]                            # the last 50 ms
print(f"{len(out)} rows: {', '.join(out.dtype.names[:4])}, ...")
print(f"amplitude over the last 50 ms: {abs(last['tipDisplacement']).max():.4e} m")
