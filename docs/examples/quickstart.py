"""Quickstart: every periodic orbit of the shrouded blade at 7000 rpm, then one run from rest into
its steady state (default parameters: the paper's Table 1). Run it with `python quickstart.py`."""
import harness

speed_rpm = 7000.0  # [rpm]
for orbit in harness.periodic_orbits(speed_rpm):  # by shooting, with Floquet stability
    print(f"orbit: max|q| = {orbit.amplitude:.6e} m ({orbit.label})")

res = harness.simulate(1.5, speed_rpm=speed_rpm)  # numpy record array: time + the FMU's outputs
last = res["time"] >= res["time"][-1] - 60 / (3 * speed_rpm)  # the last excitation period (engine order 3)
print(f"simulate: max|q| over the last period = {abs(res['tipDisplacement'][last]).max():.6e} m")
