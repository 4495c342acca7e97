"""A loaded FMU binary: its own ctypes handle with the prototype of every exported function of a
signature table set once, so `lib.fmi2DoStep(c, t, h, 1)` is a raw call returning the status int.
The handle is private to this object: other importers of the same binary (fmpy) keep theirs."""

from __future__ import annotations

import _ctypes
import ctypes
import os
from pathlib import Path
from typing import Any, Mapping

Signature = tuple[Any, list[Any]]  # (restype, argtypes)


class Library:
    def __init__(self, path: str | Path, signatures: Mapping[str, Signature], required: tuple[str, ...] = ()):
        self.path = Path(path)
        self.dll = ctypes.CDLL(str(self.path), mode=os.RTLD_NOW | os.RTLD_LOCAL)
        self.signatures = signatures
        self.exported = [n for n in signatures if hasattr(self.dll, n)]
        self.missing = [n for n in required if n not in self.exported]  # required by the standard
        for name in self.exported:
            restype, argtypes = signatures[name]
            f = getattr(self.dll, name)
            f.restype, f.argtypes = restype, argtypes
            setattr(self, name, f)  # a plain attribute: no __getattr__ on the hot path

    def __getattr__(self, name: str) -> Any:
        """An exported function outside the table (default ctypes prototype)."""
        if name.startswith(("fmi2", "fmi3")) and self.__dict__.get("dll") is not None:
            return getattr(self.dll, name)  # AttributeError if the binary does not export it
        raise AttributeError(name)

    def has(self, name: str) -> bool:
        return name in self.exported

    def close(self) -> None:
        """Unload the binary (dlclose of this handle): only after every instance of it is freed."""
        if self.dll is not None:
            for name in self.exported:
                delattr(self, name)
            _ctypes.dlclose(self.dll._handle)
            self.dll = None
