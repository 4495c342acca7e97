"""The FMU from Python: build it with CMake (build) and drive it through a ctypes/fmpy binding (blade)."""
