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


def test_an_unreliable_fit_is_a_finished_task_whose_row_says_why():
    """A fit that ran to its end but cannot be trusted is not a failed task: its row holds its
    figures, the status "unreliable" and the reasons."""
    from dataclasses import replace

    from dolphinfit.core.batch.summary import fit_values
    from tests.core.project.test_comparison import _template_fit

    unreliable = replace(_template_fit(), status="unreliable",
                         reasons=("only 3 frame(s) fitted (a fit needs 5)",))
    values = fit_values(unreliable)
    assert values["fit_status"] == "unreliable" and unreliable.finished
    assert values["fit_unreliable_because"] == "only 3 frame(s) fitted (a fit needs 5)"
    row = summary_row(TaskRecord("DJI_1-1", "DJI_1.mp4", "1", "complete", values=values))
    assert list(row) == list(COLUMNS) and row["fit_status"] == "unreliable"
