"""``python -m crslab`` is the ``crslab`` command."""

from crslab.cli import main

if __name__ == "__main__":  # guarded: a spawned worker process imports this module
    raise SystemExit(main())
