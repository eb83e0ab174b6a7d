"""``python -m studies.radial_stiffness``: :func:`studies.radial_stiffness.driver.main`."""

import sys

from studies.radial_stiffness.driver import main

sys.exit(main())
