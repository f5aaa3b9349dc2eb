"""What the app holds: the open project and its undo stack, the commands that edit it, the open
clip and frame, the user's preferences."""
