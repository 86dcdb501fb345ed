"""Rule files (YAML, npz, shards), PDDL in and out, IPC plan files."""
