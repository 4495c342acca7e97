"""The FMU from Python: build it with CMake (build), the FMI binding (binding: ctypes, FMI 2.0 and
3.0), and the wrappers on it (blade: BladeFMU; slave: the ring's name-based slave)."""
