"""Infrastructure every layer may use: errors, guarded file I/O, provenance, worker pools, backends.

Nothing here knows the blocks world; the lowest layer of the package.
"""
