"""`python -m ikea_suite` runs the same rollout as `ikea-suite-rollout`."""

import sys

from ikea_suite import cli

sys.exit(cli.main())
