"""``python -m pframe.reference MODEL.yaml``: see :mod:`pframe.reference.study`."""

import sys

from pframe.reference.study import main

sys.exit(main())
