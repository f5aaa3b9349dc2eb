"""The app's dialogs: altitude, camera, relink, shortcuts, animal and handle style."""
