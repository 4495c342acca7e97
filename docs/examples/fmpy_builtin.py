import fmpy
# the FMU's defaults: its built-in load Fw0 = 100 N/m at rotorSpeed = 5000 rpm (the paper's base case)
res = fmpy.simulate_fmu("build/ShroudedBlade.fmu", stop_time=0.3, output_interval=1e-3, output=["tipDisplacement"])
print(f"max |q| over 0.3 s: {abs(res['tipDisplacement']).max():.4e} m")
