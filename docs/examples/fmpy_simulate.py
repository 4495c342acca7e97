import numpy as np, fmpy
t = np.arange(0.0, 0.3 + 5e-6, 1e-5)  # the load table: aeroLoad = F_w0 sin(EO Omega t), F_w0 = 100 N/m, EO 3, 5000 rpm
u = np.rec.fromarrays([t, 100.0 * np.sin(3 * 5000 * np.pi / 30 * t), np.full_like(t, 5000.0)], names="time,aeroLoad,rotorSpeed")
res = fmpy.simulate_fmu("build/ShroudedBlade.fmu", stop_time=0.3, output_interval=1e-4, input=u, output=["tipDisplacement"],
                        start_values={"Fw0": 0.0})  # the load comes from the table: the FMU's built-in load off
print(f"max |q| over 0.3 s: {abs(res['tipDisplacement']).max():.4e} m")
