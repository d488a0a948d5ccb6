"""The flexible cage inside the multibody model: the reduced (Craig–Bampton) cage read into the
floating-frame arrays the dynamics integrates, and its per-step stress monitor."""
