"""Work off the GUI thread: one-shot jobs, long core jobs with progress and cancel, frame
decoding, results, exports, fits and tracking."""
