"""``python -m studies.peer``: :func:`studies.peer.driver.main`."""

import sys

from studies.peer.driver import main

sys.exit(main())
