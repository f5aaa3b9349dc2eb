"""Batches of fits and elliptical measurements run as Dask tasks, resumable.

A batch is a list of :class:`core.batch.task.BatchTask` (from a manifest CSV,
core/batch/manifest.py, or a project file, core/batch/project_tasks.py). Each task fits one
animal of one clip and measures it by the elliptical method on a Dask worker
(core/batch/task_run.py), writing its outputs and a record of its inputs' content hashes and
its status into its own folder, atomically (core/io/atomic.py). A rerun skips the tasks
whose folder records the same inputs; the summary table is rebuilt from the records
(core/batch/summary.py).
"""
