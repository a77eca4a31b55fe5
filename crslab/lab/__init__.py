"""A lab file: finding it, compiling it against the board shims, and what it declares."""
