"""The ring caches' key (harness/system/engine_identity.py): it changes when an engine source
changes, and it covers every module of harness.system and harness.analysis.periodic that a ring
branch computation loads (a module outside its folders would be an engine change no key sees)."""

from __future__ import annotations

import sys
from pathlib import Path

from harness.system import engine_identity


def test_digest_follows_an_edited_source(tmp_path, monkeypatch):
    src = tmp_path / "period_map.py"
    src.write_text("STEPS = 160\n")
    monkeypatch.setattr(engine_identity, "_SOURCES", (tmp_path,))
    monkeypatch.setattr(engine_identity, "_HERE", tmp_path / "system")
    before = engine_identity.ring_engine_digest()
    assert engine_identity.ring_engine_digest() == before  # a function of the files alone
    src.write_text("STEPS = 161\n")
    assert engine_identity.ring_engine_digest() != before


def test_digest_covers_the_modules_a_branch_run_loads():
    import harness.studies.mistuning_states  # noqa: F401  (loads the engine it keys)

    folders = {Path(f).resolve() for f in engine_identity._SOURCES}
    engine = [
        m
        for name, m in list(sys.modules.items())
        if name.startswith(("harness.system", "harness.analysis.periodic")) and getattr(m, "__file__", None)
    ]
    assert engine, "no engine module loaded"
    outside = [m.__name__ for m in engine if Path(m.__file__).resolve().parent not in folders]
    assert not outside, f"engine modules outside the digest's folders: {outside}"
