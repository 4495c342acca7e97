"""The FMU from Python (layer above model): build it with CMake (build), the FMI binding (binding: ctypes,
FMI 2.0 and 3.0), the wrappers on it (blade: BladeFMU; slave: the ring's name-based slave) and
libcosim's time (libcosim)."""
