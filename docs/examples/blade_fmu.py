from harness.fmu.blade import BladeFMU
from harness.model.excitation import LinearRamp

# One instance, several runs (each run resets the FMU): a constant speed with the inputs held over
# each step, and a run-up 4000 -> 6000 rpm with the load's derivatives up to order 8 (the default).
with BladeFMU() as fmu:
    held = fmu.run({"Fw0": 100.0}, stop_time=0.3, step=1e-4, speed_rpm=5000.0, derivative_order=0)
    runup = fmu.run({"Fw0": 100.0}, stop_time=0.3, step=1e-4, speed_rpm=LinearRamp(4000.0, 6000.0, 0.0, 0.3))
print(f"held inputs: max |q| = {abs(held['tipDisplacement']).max():.4e} m")
print(f"run-up: max |q| = {abs(runup['tipDisplacement']).max():.4e} m")
