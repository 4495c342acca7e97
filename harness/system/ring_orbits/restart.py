"""The period map's calls on the ring's instances around each period: every instance restarted at
t = 0 with its parameters and start values (`Restarts`), and the state read back (`Reads`), each
one call into the C loop's library (harness/native/ring_restart.c). The value arrays are built once;
only the start values change between periods (the binding's checked calls, one ctypes call each,
cost a tenth of a 6-blade period)."""

from __future__ import annotations

import ctypes as C
from typing import Any, Mapping, Sequence

import numpy as np

from harness.fmu.binding import FmiError
from harness.fmu.slave import Slave
from harness.system.ring_c import _library

_FUNCTIONS = (
    "fmi2Reset",
    "fmi2SetupExperiment",
    "fmi2SetReal",
    "fmi2SetInteger",
    "fmi2SetBoolean",
    "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode",
)


class _Api(C.Structure):
    _fields_ = [(f, C.c_void_p) for f in _FUNCTIONS]


class _Instance(C.Structure):
    _fields_ = [
        ("c", C.c_void_p),
        ("realVr", C.POINTER(C.c_uint)),
        ("real", C.POINTER(C.c_double)),
        ("nReal", C.c_size_t),
        ("intVr", C.POINTER(C.c_uint)),
        ("ints", C.POINTER(C.c_int)),
        ("nInt", C.c_size_t),
        ("boolVr", C.POINTER(C.c_uint)),
        ("bools", C.POINTER(C.c_int)),
        ("nBool", C.c_size_t),
    ]


_function: Any = None
_reads: Any = None


def _restart_function() -> Any:
    """ringRestart of the C loop's library, its signature declared once."""
    global _function
    if _function is None:
        f = _library().ringRestart
        f.argtypes = [C.POINTER(_Api), C.POINTER(_Instance), C.c_int, C.POINTER(C.c_int), C.POINTER(C.c_int)]
        f.restype = C.c_int
        _function = f
    return _function


def _reads_function() -> Any:
    """ringReads of the C loop's library, its signature declared once."""
    global _reads
    if _reads is None:
        f = _library().ringReads
        f.argtypes = [
            C.c_void_p,
            C.POINTER(C.c_void_p),
            C.c_int,
            C.POINTER(C.c_uint),
            C.c_size_t,
            C.POINTER(C.c_double),
            C.POINTER(C.c_int),
            C.POINTER(C.c_int),
        ]
        f.restype = C.c_int
        _reads = f
    return _reads


def _typed(slave: Slave, params: Mapping[str, Any]) -> dict[str, tuple[list[int], list[Any]]]:
    """type -> (value references, values: floats for Real, ints for Integer and Boolean)."""
    groups: dict[str, tuple[list[int], list[Any]]] = {"Real": ([], []), "Integer": ([], []), "Boolean": ([], [])}
    for k, v in params.items():
        var = slave.u.vars[k]
        t = var.type if var.type in groups else "Boolean"
        groups[t][0].append(var.valueReference)
        groups[t][1].append(float(v) if t == "Real" else int(v))
    return groups


class Restarts:
    """fmi2Reset, fmi2SetupExperiment at t = 0, the parameters and then the start values (one
    fmi2SetReal), the Integer and Boolean parameters, fmi2EnterInitializationMode and
    fmi2ExitInitializationMode of every instance of one binary, in turn. `starts` (instances, start
    names), a view on the values handed to fmi2SetReal, takes the start values before each call."""

    def __init__(self, members: Sequence[tuple[Slave, Mapping[str, Any]]], starts: list[str]):
        self.slaves = [s for s, _ in members]
        typed = [_typed(s, p) for s, p in members]
        ns = len(starts)
        width = max(len(g["Real"][0]) for g in typed) + ns
        # row i: padding, instance i's Real parameters, its start values (the last ns columns)
        self._values = (C.c_double * (width * len(members)))()
        rows = np.frombuffer(self._values, dtype=np.float64).reshape(len(members), width)  # type: ignore[call-overload]
        self.starts = rows[:, width - ns :]
        self._keep: list[Any] = []  # the ctypes arrays the structs point into
        items = []
        for i, ((slave, _), g) in enumerate(zip(members, typed)):
            n_real = len(g["Real"][0]) + ns
            first = width - n_real
            rows[i, first : width - ns] = g["Real"][1]
            vr = (C.c_uint * n_real)(*g["Real"][0], *[slave.vr(n) for n in starts])
            real = C.cast(C.addressof(self._values) + 8 * (i * width + first), C.POINTER(C.c_double))
            arrays = [
                ((C.c_uint * len(g[t][0]))(*g[t][0]), (C.c_int * len(g[t][1]))(*g[t][1]))
                for t in ("Integer", "Boolean")
            ]
            self._keep += [vr, *arrays]
            (iv, ii), (bv, bb) = arrays
            items.append(
                _Instance(slave.s.c, vr, real, n_real, iv, ii, len(g["Integer"][0]), bv, bb, len(g["Boolean"][0]))
            )
        self._items = (_Instance * len(items))(*items)
        dll = self.slaves[0].s.lib.dll
        self._api = _Api(*(C.cast(getattr(dll, f), C.c_void_p) for f in _FUNCTIONS))
        self._restart = _restart_function()

    def __call__(self) -> None:
        """Restarts every instance; raises FmiError naming the call that failed and the instance's
        last message."""
        failed, status = C.c_int(-1), C.c_int(0)
        rc = self._restart(C.byref(self._api), self._items, len(self.slaves), C.byref(failed), C.byref(status))
        if rc:
            slave = self.slaves[failed.value]
            raise FmiError(_FUNCTIONS[rc - 1], status.value, slave.messages[-1] if slave.messages else None)


class Reads:
    """fmi2GetReal of the same variables from every instance of a group into one (instances, variables)
    array: one call into the C loop's library (ringReads) with the arrays built once."""

    def __init__(self, slaves: Sequence[Slave], names: list[str]):
        self.slaves, k = slaves, len(names)
        self.vr = (C.c_uint * k)(*[slaves[0].vr(n) for n in names])
        self.out = (C.c_double * (k * len(slaves)))()
        self._handles = (C.c_void_p * len(slaves))(*(s.s.c for s in slaves))
        self._get = C.cast(slaves[0].s.lib.dll.fmi2GetReal, C.c_void_p)
        self._reads = _reads_function()
        # a view on the ctypes array (a buffer; typeshed's numpy stubs do not say so)
        self.values = np.frombuffer(self.out, dtype=np.float64).reshape(len(slaves), k)  # type: ignore[call-overload]

    def __call__(self) -> np.ndarray:
        """A copy of the values now, row i instance i's."""
        failed, status = C.c_int(-1), C.c_int(0)
        if self._reads(
            self._get,
            self._handles,
            len(self.slaves),
            self.vr,
            len(self.vr),
            self.out,
            C.byref(failed),
            C.byref(status),
        ):
            s = self.slaves[failed.value]
            raise FmiError("fmi2GetReal", status.value, s.messages[-1] if s.messages else None)
        out: np.ndarray = self.values.copy()
        return out
