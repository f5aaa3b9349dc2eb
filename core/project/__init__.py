"""Projects: clips, animals and measured frames, their file, edits and per-animal results."""
