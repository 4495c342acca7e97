"""FMU state: get/set, serialize/deserialize (also in a new process), reset, and bad state blobs.

A run continued from a saved FMU state must be bit-identical to the uninterrupted run: the
reference is the FMU's own uninterrupted run under exactly the same inputs (arrays compared with
np.array_equal, no tolerance: the state holds every double of the solver, so any difference is a
lost or rounded field). The same holds after fmi2Reset (a rerun equals the first run and a fresh
instance) and for a serialized state restored in a fresh instance, in this process or in a new
Python process that loads the blob from a file. Corrupted, truncated, extended or wrong-version
blobs must give fmi2Error; a blob whose checksum was recomputed after a change must be validated
on content (fmi2Error) or, if its content is legal, be safe to use.
"""

from __future__ import annotations

import math
import os
import struct
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from tests.support import fmi2raw as F
from tests.support.fmi2raw import ERROR, OK, Fmi2Library, Instance

H = 1e-4  # communication step [s]

# parameter sets covering the discrete state of every friction model and amplitude mode
PARAM_SETS = {
    "macroslipDF-tracked": {},
    "coulombDF-fixed": {"frictionModel": 2, "amplitudeMode": 1},
    "jenkins-TD": {"frictionModel": 3, "d": 2e-5},
    "consistent-nogating": {"formulation": 2, "projection": 2, "gating": False},
}


def ready(lib: Fmi2Library, params: dict | None = None) -> Instance:
    c = Instance(lib)
    assert c.ok
    assert c.initialize(params or {}) == OK, c.log_text()
    return c


def run(c: Instance, k0: int, n: int, Fw0: float = 300.0) -> np.ndarray:
    st, out = F.run_steps(c, k0 * H, H, n, Fw0=Fw0)
    assert st == OK, c.log_text()
    return out


def snapshot(c: Instance) -> bytes:
    st, s = c.get_state()
    assert st == OK and s
    st, blob = c.serialize(s)
    assert st == OK and blob
    assert c.free_state(s) == OK
    return blob


@pytest.mark.parametrize("name", list(PARAM_SETS))
def test_get_set_state_continues_bit_identically(lib: Fmi2Library, name: str) -> None:
    params = PARAM_SETS[name]
    with ready(lib, params) as c:
        head = run(c, 0, 400)
        st, s1 = c.get_state()
        assert st == OK
        tail = run(c, 400, 600)
        st, s2 = c.get_state()  # a second state, then go back to the first, then the second
        assert st == OK
        more = run(c, 1000, 100)
        assert c.set_state(s1) == OK
        assert np.array_equal(run(c, 400, 600), tail)
        assert c.set_state(s2) == OK
        assert np.array_equal(run(c, 1000, 100), more)
        # fmi2GetFMUstate into an existing handle overwrites it
        assert c.set_state(s1) == OK
        st, same = c.get_state(s2)
        assert st == OK and same == s2
        assert c.set_state(s2) == OK
        assert np.array_equal(run(c, 400, 600), tail)
        assert c.free_state(s1) == OK and c.free_state(s2) == OK
        assert head.shape == (400, len(F.REAL_OUTPUTS) + len(F.INT_OUTPUTS))
        assert np.all(np.isfinite(head)) and np.all(np.isfinite(tail))
        assert np.any(tail[:, 0] != 0.0)  # the blade moved: the comparison is not vacuous


@pytest.mark.parametrize("name", list(PARAM_SETS))
def test_serialized_state_in_fresh_instances(lib: Fmi2Library, name: str) -> None:
    params = PARAM_SETS[name]
    with ready(lib, params) as a:
        run(a, 0, 500)
        blob = snapshot(a)
        tail = run(a, 500, 500)
        st, tl = a.get_real_status(F.LAST_SUCCESSFUL_TIME)
        assert st == OK and tl == pytest.approx(1000 * H, rel=0, abs=1e-12)
    # (1) a fresh instance that was never initialized
    with Instance(lib) as b:
        st, s = b.deserialize(blob)
        assert st == OK and s, b.log_text()
        assert b.set_state(s) == OK, b.log_text()
        assert np.array_equal(run(b, 500, 500), tail)
        b.free_state(s)
    # (2) a fresh instance initialized with the default parameters: the state carries the
    #     parameters, so it continues the saved run, not a default one
    with ready(lib) as b:
        run(b, 0, 10)
        st, s = b.deserialize(blob)
        assert st == OK
        assert b.set_state(s) == OK
        assert np.array_equal(run(b, 500, 500), tail)
        # serializing the restored state gives the same bytes
        assert snapshot(b) != blob  # it moved on
        assert b.set_state(s) == OK
        assert snapshot(b) == blob
        b.free_state(s)


CHILD = textwrap.dedent("""
    import sys, numpy as np
    from tests.support import fmi2raw as F  # run from the repository root (cwd)
    blob = open(sys.argv[2], "rb").read()
    k0, n = int(sys.argv[4]), int(sys.argv[5])
    with F.Instance() as c:
        st, s = c.deserialize(blob)
        assert st == F.OK, c.log_text()
        assert c.set_state(s) == F.OK, c.log_text()
        st, out = F.run_steps(c, k0 * 1e-4, 1e-4, n, Fw0=300.0)
        assert st == F.OK, c.log_text()
        np.save(sys.argv[3], out)
""")


def test_deserialize_in_a_new_process(lib: Fmi2Library, tmp_path: Path) -> None:
    with ready(lib, PARAM_SETS["jenkins-TD"]) as a:
        run(a, 0, 700)
        blob = snapshot(a)
        tail = run(a, 700, 800)
    (tmp_path / "state.bin").write_bytes(blob)
    proc = subprocess.run(
        [
            sys.executable,
            "-c",
            CHILD,
            str(Path(__file__).parent),
            str(tmp_path / "state.bin"),
            str(tmp_path / "out.npy"),
            "700",
            "800",
        ],
        capture_output=True,
        text=True,
        timeout=300,
        env=os.environ.copy(),
        cwd=Path(__file__).resolve().parents[2],
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    other = np.load(tmp_path / "out.npy")
    assert np.array_equal(other, tail)


@pytest.mark.parametrize("name", list(PARAM_SETS))
def test_reset_then_rerun_is_bit_identical(lib: Fmi2Library, name: str) -> None:
    params = PARAM_SETS[name]
    with ready(lib, params) as c:
        first = run(c, 0, 800)
        assert c.terminate() == OK
        assert c.reset() == OK
        assert c.initialize(params) == OK
        assert np.array_equal(run(c, 0, 800), first)
        # reset in the middle of a run (no terminate), then rerun
        run(c, 800, 50)
        assert c.reset() == OK
        assert c.initialize(params) == OK
        assert np.array_equal(run(c, 0, 800), first)
    with ready(lib, params) as fresh:
        assert np.array_equal(run(fresh, 0, 800), first)


def test_reset_restores_start_values(lib: Fmi2Library) -> None:
    # after a run with other parameters, fmi2Reset without setting any parameter = defaults
    with ready(lib) as d:
        defaults = run(d, 0, 300)
    with ready(lib, {"frictionModel": 2, "kn": 1e6, "d": 1e-5, "engineOrder": 2}) as c:
        other = run(c, 0, 300)
        assert not np.array_equal(other, defaults)
        assert c.reset() == OK
        assert c.initialize() == OK
        assert np.array_equal(run(c, 0, 300), defaults)


@pytest.mark.parametrize(
    "change", [{"EI": 300.0}, {"m0": 0.05}, {"l": 0.11}, {"c": 2.0}, {"formulation": 2}, {"rho": 7000.0}, {"A": 1.1e-4}]
)
def test_reset_with_another_blade_equals_a_fresh_instance(lib: Fmi2Library, change: dict) -> None:
    # the instance keeps its last Galerkin reduction across fmi2Reset (shooting restarts the same
    # blade thousands of times): a changed blade parameter or formulation must not reuse it
    with ready(lib) as c:
        first = run(c, 0, 200)
        assert c.reset() == OK
        assert c.initialize(change) == OK
        changed = run(c, 0, 200)
        assert c.reset() == OK
        assert c.initialize() == OK
        again = run(c, 0, 200)
    with ready(lib, change) as fresh:
        expected = run(fresh, 0, 200)
    assert np.array_equal(changed, expected)
    assert not np.array_equal(changed, first)
    assert np.array_equal(again, first)


def test_restore_after_an_error(lib: Fmi2Library) -> None:
    # fmi2SetFMUstate is the standard's way out of an fmi2Error: continue as if nothing happened
    with ready(lib) as c:
        run(c, 0, 200)
        st, s = c.get_state()
        tail = run(c, 200, 200)
        assert c.set_state(s) == OK
        assert c.do_step(0.123, H) == ERROR  # wrong communication point
        assert c.set_state(s) == OK, c.log_text()
        assert np.array_equal(run(c, 200, 200), tail)
        c.free_state(s)


# ---------------------------------------------------------------------------------------------
# bad blobs


fnv1a, reseal = F.fnv1a, F.reseal


@pytest.fixture(scope="module")
def blob(lib: Fmi2Library) -> bytes:
    with ready(lib, PARAM_SETS["jenkins-TD"]) as c:
        run(c, 0, 300)
        b = snapshot(c)
    # the documented layout: magic, version 6, total size, ..., FNV-1a 64 trailer
    assert b[:8] == b"SBLDSTAT"
    assert struct.unpack_from("<i", b, 8)[0] == 6
    assert struct.unpack_from("<i", b, 12)[0] == len(b)
    assert reseal(b) == b
    return b


def deserialize(lib: Fmi2Library, data: bytes, size: int | None = None) -> tuple[int, Instance]:
    c = Instance(lib)
    st, s = c.deserialize(data, size)
    if s:
        c.free_state(s)
    return st, c


def test_truncated_blobs_give_error(lib: Fmi2Library, blob: bytes) -> None:
    for n in range(len(blob)):
        st, c = deserialize(lib, blob[:n])
        assert st == ERROR, f"length {n}: {st}"
        assert c.messages(F.ERROR), f"length {n}: no message"
        c.free()
    st, c = deserialize(lib, blob + b"\0")
    assert st == ERROR
    c.free()
    st, c = deserialize(lib, blob, 0)
    assert st == ERROR
    c.free()


def test_every_single_byte_corruption_gives_error(lib: Fmi2Library, blob: bytes) -> None:
    with Instance(lib) as c:
        for i in range(len(blob)):
            for mask in (0x01, 0x80, 0xFF):
                bad = blob[:i] + bytes([blob[i] ^ mask]) + blob[i + 1 :]
                st, s = c.deserialize(bad)
                if s:
                    c.free_state(s)
                assert st == ERROR, f"byte {i} ^ {mask:#x} accepted"


def test_wrong_version_gives_error_naming_the_version(lib: Fmi2Library, blob: bytes) -> None:
    # 1: before the start values of jenkinsForce and runningMaximum, 2: with the state machine,
    # 3: before the sensitivities, 4: before the built-in load, 5: before the modes, 7: a future one
    for version in (0, 1, 2, 3, 4, 5, 7, -1, 2**31 - 1):
        bad = reseal(blob[:8] + struct.pack("<i", version) + blob[12:])
        st, c = deserialize(lib, bad)
        assert st == ERROR
        assert any(str(version) in (r.message or "") and "version" in (r.message or "") for r in c.log), c.log_text()
        c.free()


def test_resealed_content_is_validated(lib: Fmi2Library, blob: bytes) -> None:
    """Valid checksum, illegal content: every double set to NaN/inf/-1e308 and every int32 to
    extreme values in turn. Refused with fmi2Error, or, if the content is legal, usable without a
    crash and giving finite outputs whenever a step returns OK."""
    ndouble, nint = struct.unpack_from("<ii", blob, 24)
    offsets = [(32 + 8 * i, "<d", v) for i in range(ndouble) for v in (math.nan, math.inf, -1e308)]
    base = 32 + 8 * ndouble
    offsets += [(base + 4 * i, "<i", v) for i in range(nint) for v in (-1, 7, -(2**31), 2**31 - 1)]
    accepted = 0
    with Instance(lib) as c:
        for off, fmt, v in offsets:
            bad = bytearray(blob)
            struct.pack_into(fmt, bad, off, v)
            st, s = c.deserialize(reseal(bytes(bad)))
            assert st in (OK, ERROR)
            if st == OK:
                accepted += 1
                assert c.set_state(s) == OK
                st2, tl = c.get_real_status(F.LAST_SUCCESSFUL_TIME)
                if st2 == OK and abs(tl) < 1e6:
                    st3, out = F.run_steps(c, tl, H, 3)
                    assert st3 in F.VALID_STATUSES
                    if st3 == OK:
                        assert np.all(np.isfinite(out))
                c.reset()
            if s:
                c.free_state(s)
    # NaN in any double and an initialized flag of 7 (not 0 or 1) are always illegal
    assert accepted < len(offsets)


def test_blob_from_a_different_fmu_gives_error(lib: Fmi2Library, blob: bytes) -> None:
    bad = reseal(blob[:16] + struct.pack("<Q", fnv1a(b"{another-guid}")) + blob[24:])
    st, c = deserialize(lib, bad)
    assert st == ERROR
    c.free()
