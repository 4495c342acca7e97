"""The mistuning study on a real dask.distributed scheduler: the speed-up from 1 to 2 workers, a worker killed mid-run, the cluster's cost.

`python -m harness mistuning-dask [--out FILE]` runs harness.studies.mistuning_dask's measurement
(a few minutes on 2 cores; needs the `cluster` extra) and writes it to FILE as JSON.
"""

from __future__ import annotations

import argparse
import json

from harness.outputs import check_file
from harness.studies.mistuning_dask import write_measurement


def configure_parser(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--out",
        default="mistuning_dask.json",
        metavar="FILE",
        help="where the JSON goes (default ./mistuning_dask.json)",
    )


def run(args: argparse.Namespace) -> int:
    check_file(args.out, "--out")  # before the measurement
    m = write_measurement(args.out)
    print(json.dumps({k: m[k] for k in ("speed_up", "efficiency", "sweep_s", "sweep_cpu_s", "cluster_cost")}))
    print(m["killed_worker"])
    return 0
