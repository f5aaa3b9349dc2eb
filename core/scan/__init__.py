"""The scan of a clip: the animals in view and the frames worth measuring them in."""
