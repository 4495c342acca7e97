"""The FMU from Python (layer above model): build it with CMake (build), drive it through a ctypes/fmpy
binding (blade), the ring FMUs as fmpy slaves (slave) and libcosim's time (libcosim)."""
