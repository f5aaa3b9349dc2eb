"""Running a batch's tasks on a Dask client and collecting their records into the summary.

Dask's own retry does not apply: a task that raises is a bug or a lost worker, recorded as
failed; the tasks themselves record their failures (core/batch/task_run.py).

Each task's result is let go as soon as its record is taken: Dask runs again the tasks whose
results a lost worker held while a client still wants them, so a worker killed late in a
batch would run every task it had finished once more (a failed one, with ``retry_failed``,
to completion a second time; the others to report themselves as reused).
"""

from collections.abc import Callable, Sequence
from pathlib import Path

from distributed import Client, as_completed

from dolphinfit.core.batch.record import STATUS_FAILED, TaskRecord
from dolphinfit.core.batch.summary import SUMMARY_CSV, write_summary
from dolphinfit.core.batch.task import BatchTask
from dolphinfit.core.batch.task_run import describe, run_task
from dolphinfit.core.device import CPU


def run_batch(client: Client, tasks: Sequence[BatchTask], out_dir: Path,
              retry_failed: bool = False,
              on_record: Callable[[int, TaskRecord], None] | None = None,
              device: str = CPU) -> list[TaskRecord]:
    """Run every task (finished ones are skipped by the tasks themselves), write
    ``out_dir/summary.csv`` and return the records in the tasks' order; ``on_record`` gets
    each task's index and record as it finishes. ``device`` names where the fits compute
    (core.device), resolved on each worker."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    futures = [client.submit(run_task, task, out_dir, retry_failed, device, pure=False)
               for task in tasks]
    position = {future.key: i for i, future in enumerate(futures)}
    records: list[TaskRecord | None] = [None] * len(tasks)
    for future in as_completed(futures):
        i = position[future.key]
        try:
            record = future.result()
        except Exception as exc:  # noqa: BLE001 (a lost worker: recorded, the batch goes on)
            task = tasks[i]
            record = TaskRecord(task.name, task.clip, task.animal_id, STATUS_FAILED,
                                f"the task did not finish: {describe(exc)}")
        future.release()
        records[i] = record
        if on_record is not None:
            on_record(i, record)
    write_summary(out_dir / SUMMARY_CSV, records)
    return records
