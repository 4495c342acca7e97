"""The paper's studies with Fig. 2: harness.studies.paper's studies, then the hysteresis loop of
Fig. 2 (the FMU's friction loop against the reference's, `hysteresis`), then summary.json.

What the `reproduce` and `run` commands run. Fig. 2 is the one figure that needs the reference,
which is why it is added here, above the studies, and not inside them.
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path
from typing import Any, Mapping, Sequence

from harness.analysis.cache import fmu_identity
from harness.paths import RESULTS_DIR
from harness.analysis.executor import Runner
from harness.fmu.blade import BladeFMU
from harness.studies import paper
from harness.validation.hysteresis import hysteresis


def reproduce(
    out: Path | str = RESULTS_DIR,
    size: str | paper.Size = "default",
    studies: Sequence[str] | None = None,
    runner: Runner | None = None,
    fmu_path: Path | str | None = None,
    extras: bool = True,
    base: Mapping[str, Any] | None = None,
) -> paper.Reproduction:
    """harness.studies.paper.run_studies, with `extras` also Fig. 2 (its time counted in the extras'
    wall time), then summary.json."""
    out = Path(out)
    rep = paper.run_studies(out, size, studies, runner, fmu_path, extras, base)
    summary = rep.summary
    if extras:
        t0 = time.perf_counter()
        with BladeFMU(fmu_identity(fmu_path)[0]) as fmu:
            summary.hysteresis = hysteresis(fmu, out, summary.base)
        if summary.timing is not None and summary.timing.extras_wall is not None:
            summary.timing = dataclasses.replace(
                summary.timing, extras_wall=summary.timing.extras_wall + time.perf_counter() - t0
            )
    paper.write_summary(out, summary)
    return rep
