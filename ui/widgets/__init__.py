"""What the user sees and touches: the frame view and its overlays, the timeline, the panels
and the 3D view."""
