"""The fault drill's count of completions: each time a task's folder is written whole, the
watch sees one more; looking again at the same folder adds none."""

from dolphinfit.core.batch.record import STATUS_COMPLETE, TaskRecord, write_record
from dolphinfit.core.bench.record_watch import RecordWatch
from dolphinfit.core.io.atomic import atomic_folder


def _complete(out, name):
    """What a task's run does with its folder (core/batch/task_run.py)."""
    with atomic_folder(out / name) as partial:
        write_record(partial, TaskRecord(name, "clip.mkv", "1", STATUS_COMPLETE))


def test_each_whole_write_of_a_task_folder_is_one_completion(tmp_path):
    watch = RecordWatch(tmp_path, ["a", "b"])
    assert watch.poll() == 0
    _complete(tmp_path, "a")
    assert watch.poll() == 1 and watch.poll() == 1
    assert watch.completions() == {"a": 1, "b": 0}
    _complete(tmp_path, "a")  # the same task completed again
    _complete(tmp_path, "b")
    assert watch.poll() == 2
    assert watch.completions() == {"a": 2, "b": 1}
    assert set(watch.current()) == {"a", "b"}
