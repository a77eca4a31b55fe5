"""``python -m crslab`` is the ``crslab`` command."""

from crslab.cli import main

raise SystemExit(main())
