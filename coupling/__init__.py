"""The flexible cage inside the multibody model, scenes, results files, CLI and reports."""
