"""`python -m harness ...`: see harness/cli/main.py."""

from harness.cli.main import main

raise SystemExit(main())
