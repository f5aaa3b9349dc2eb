"""The batch summary's rows: every column present, and the image ID of a task finished before
the column was named ``Image_ID`` kept under its new name."""

from dolphinfit.core.batch.record import TaskRecord
from dolphinfit.core.batch.summary import COLUMNS, summary_row


def test_a_task_finished_before_the_rename_keeps_its_image_id():
    old = TaskRecord("DJI_1-1", "DJI_1.mp4", "1", "complete",
                     values={"Image": "DJI_1_f000012", "ell_frame": 12, "length_m_ell": 2.4})
    row = summary_row(old)
    assert list(row) == list(COLUMNS)
    assert (row["Image_ID"], row["ell_frame"], row["length_m_ell"]) == ("DJI_1_f000012", 12, 2.4)
    assert row["volume_m3_fit"] == "" and row["reused"] == "no"
