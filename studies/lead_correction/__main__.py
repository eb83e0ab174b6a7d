"""``python -m studies.lead_correction``: :func:`studies.lead_correction.driver.main`."""

import sys

from studies.lead_correction.driver import main

sys.exit(main())
