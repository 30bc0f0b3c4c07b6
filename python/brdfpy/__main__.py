"""``python -m brdfpy``: the same as the ``brdfpy`` command."""

from brdfpy.cli import main

raise SystemExit(main())
