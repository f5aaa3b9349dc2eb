"""The frame picker: one animal of the selected clip's scan at a time, its sampled frames with
a picture of the animal and their scores (core/scan/frame_scores.py), best first and sortable
by any column. Enter (or a double click) measures the animal on that frame; Delete puts the
frame aside for this animal or takes it back. Frames put aside, or with a fault, are listed
below the usable ones only when "show frames put aside" is ticked. The table shows the columns
that fit the dock's width, left to right, rather than scroll sideways; a row's tooltip gives
every score."""

import numpy as np
from PySide6.QtCore import QSize, Qt, Signal
from PySide6.QtGui import QIcon, QKeyEvent, QPixmap, QResizeEvent
from PySide6.QtWidgets import (
    QAbstractItemView, QCheckBox, QComboBox, QLabel, QTableWidget,
    QTableWidgetItem, QVBoxLayout, QWidget,
)

from dolphinfit.core.project.scan_store import usable_frames
from dolphinfit.core.scan.clip_scan import ClipScan
from dolphinfit.core.scan.frame_scores import FrameScore
from dolphinfit.ui.workers.frame_loader import rgb_to_qimage

THUMBNAIL_PX = 72
COLUMNS = ("animal", "rank", "frame", "quality", "length m", "time s", "length %",
           "straight", "sharp %", "contrast %", "put aside because")
ROLE_FRAME = Qt.ItemDataRole.UserRole
KEYS_TIP = ("Enter or double click: measure this frame · Delete: put it aside (or take it "
            "back) · click a heading to sort · widen the dock for more columns")
ALWAYS_SHOWN = 3   # rank and frame, whatever the width (column 0, the animal, is never shown)


def _number(value: float, digits: int) -> QTableWidgetItem:
    """A cell that shows ``value`` rounded and sorts by it; empty for NaN."""
    item = QTableWidgetItem()
    if np.isfinite(value):
        item.setData(Qt.ItemDataRole.DisplayRole, round(float(value), digits))
    item.setFlags(item.flags() & ~Qt.ItemFlag.ItemIsEditable)
    return item


class _Table(QTableWidget):
    """The frames' table: Enter and Delete are the picker's keys, not the table's."""

    key_pressed = Signal(int)

    def fit_columns(self) -> None:
        """Show the columns, left to right, that fit the width whole and hide the rest (a
        narrower one further right too: the order of the columns is kept)."""
        room = self.viewport().width()
        header = self.horizontalHeader()
        for column in range(1, self.columnCount()):
            self.setColumnHidden(column, False)   # a hidden column's heading has no size hint
            width = max(self.sizeHintForColumn(column), header.sectionSizeHint(column))
            room -= width
            shown = column < ALWAYS_SHOWN or room >= 0
            self.setColumnHidden(column, not shown)
            if shown:
                self.setColumnWidth(column, width)

    def resizeEvent(self, event: QResizeEvent) -> None:  # noqa: N802 (Qt's name)
        super().resizeEvent(event)
        self.fit_columns()

    def keyPressEvent(self, event: QKeyEvent) -> None:  # noqa: N802 (Qt's name)
        if event.key() in (Qt.Key.Key_Return, Qt.Key.Key_Enter, Qt.Key.Key_Delete):
            self.key_pressed.emit(event.key())
            return
        super().keyPressEvent(event)


class FramePicker(QWidget):
    """Shows a scan; ``frame_chosen(animal, frame)`` to measure, ``reject_toggled(animal,
    frame)`` to put aside or take back, ``thumbnails_wanted(list[FrameScore])`` for the
    pictures of the rows shown (answered by ``set_thumbnails``)."""

    frame_chosen = Signal(int, int)
    reject_toggled = Signal(int, int)
    thumbnails_wanted = Signal(object)

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self._scan: ClipScan | None = None
        self._rejected: set[tuple[int, int]] = set()
        self._pictures: dict[tuple[int, int], QPixmap] = {}  # by (animal, frame)
        self._asked: set[tuple[int, int]] = set()  # pictures asked for
        self.animal_box = QComboBox()
        self.animal_box.currentIndexChanged.connect(lambda _: self._fill())
        self.show_aside = QCheckBox("show frames put aside")
        self.show_aside.toggled.connect(lambda _: self._fill())
        self.summary = QLabel("Not scanned: Clip → Scan this clip (Ctrl+K)")
        self.summary.setWordWrap(True)
        self.table = _Table(0, len(COLUMNS))
        self.table.setHorizontalHeaderLabels(COLUMNS)
        self.table.setColumnHidden(0, True)  # the animal: the box above says which
        self.table.setIconSize(QSize(THUMBNAIL_PX, THUMBNAIL_PX))
        self.table.verticalHeader().setDefaultSectionSize(THUMBNAIL_PX + 4)
        self.table.verticalHeader().setVisible(False)
        self.table.setSelectionBehavior(QAbstractItemView.SelectionBehavior.SelectRows)
        self.table.setSelectionMode(QAbstractItemView.SelectionMode.SingleSelection)
        self.table.setEditTriggers(QAbstractItemView.EditTrigger.NoEditTriggers)
        self.table.setToolTip(KEYS_TIP)
        self.table.cellDoubleClicked.connect(lambda row, _: self._choose(row))
        self.table.key_pressed.connect(self._on_key)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.addWidget(self.animal_box)
        layout.addWidget(self.show_aside)
        layout.addWidget(self.summary)
        layout.addWidget(self.table, stretch=1)

    # ----- what is shown
    def set_scan(self, scan: ClipScan | None, rejected: tuple[tuple[int, int], ...]) -> None:
        """The selected clip's scan (None: not scanned) and its frames put aside."""
        keep = self.current_animal()
        if scan is not self._scan:
            self._pictures.clear()
            self._asked.clear()
        self._scan, self._rejected = scan, set(rejected)
        self.animal_box.blockSignals(True)
        self.animal_box.clear()
        for number in ([] if scan is None else scan.animal_ids()):
            scores = scan.of_animal(number)
            usable = len(usable_frames(scan, self._rejected, number))
            self.animal_box.addItem(f"animal {number}: {usable} usable", number)
            self.animal_box.setItemData(self.animal_box.count() - 1,
                                        f"seen in {len(scores)} sampled frames, usable in "
                                        f"{usable}", Qt.ItemDataRole.ToolTipRole)
        if keep is not None and self.animal_box.findData(keep) >= 0:
            self.animal_box.setCurrentIndex(self.animal_box.findData(keep))
        self.animal_box.blockSignals(False)
        self._fill()

    def current_animal(self) -> int | None:
        data = self.animal_box.currentData()
        return None if data is None else int(data)

    @property
    def scan(self) -> ClipScan | None:
        return self._scan

    def set_thumbnails(self, pictures: dict[tuple[int, int], np.ndarray],
                       scan: ClipScan) -> None:
        """Pictures of ``scan``'s animals by (animal, frame), answering ``thumbnails_wanted``
        (dropped when another scan is shown now)."""
        if scan is not self._scan:
            return
        for key, rgb in pictures.items():
            self._pictures[key] = QPixmap.fromImage(rgb_to_qimage(rgb))
        number = self.current_animal()
        for row in range(self.table.rowCount()):
            item = self.table.item(row, 2)
            picture = self._pictures.get((number, item.data(ROLE_FRAME)))
            if picture is not None:
                item.setIcon(QIcon(picture))
        self.table.fit_columns()  # the pictures widen the frame numbers' column

    def _rows(self, number: int) -> list[tuple[FrameScore, str]]:
        """The animal's frames to list, each with why it is put aside ("" when usable):
        usable ones best first, then (when asked) the others."""
        usable = usable_frames(self._scan, self._rejected, number)
        rows = [(score, "") for score in usable]
        if self.show_aside.isChecked():
            listed = {score.frame_idx for score in usable}
            for score in self._scan.of_animal(number):
                if score.frame_idx not in listed:
                    mine = "put aside by you" if (number, score.frame_idx) in self._rejected \
                        else ""
                    rows.append((score, "; ".join(filter(None, (mine, *score.faults)))))
        return rows

    def _fill(self) -> None:
        table, number = self.table, self.current_animal()
        row = table.currentRow()
        kept = self._frame_at(row) if row >= 0 else None  # the row the user was on
        table.setSortingEnabled(False)
        table.setRowCount(0)
        if self._scan is None or number is None:
            self.summary.setText("Not scanned: Clip → Scan this clip (Ctrl+K)"
                                 if self._scan is None else
                                 f"No animal found in {len(self._scan.sampled_frames)} "
                                 "sampled frames")
            return
        rows = self._rows(number)
        best = self._scan.settings.best_count
        usable = sum(not why for _, why in rows)
        self.summary.setText(f"{usable} usable frame{'s' if usable != 1 else ''} of animal "
                             f"{number}; the best {min(best, usable)} ranked. Enter measures "
                             "it (as \"dolphin " f"{number}\"), Delete puts a frame aside.")
        table.setRowCount(len(rows))
        for row, (score, why) in enumerate(rows):
            rank = row + 1 if not why and row < best else float("nan")
            frame = _number(score.frame_idx, 0)
            frame.setData(ROLE_FRAME, score.frame_idx)
            if (number, score.frame_idx) in self._pictures:
                frame.setIcon(QIcon(self._pictures[number, score.frame_idx]))
            cells = [_number(number, 0), _number(rank, 0), frame, _number(score.quality, 2),
                     _number(score.length_m, 2), _number(score.time_s, 2),
                     _number(100 * score.length_share, 0), _number(score.straightness, 3),
                     _number(100 * score.sharpness_share, 0),
                     _number(100 * score.contrast_share, 0), QTableWidgetItem(why)]
            tip = "\n".join([f"{name}: {cell.text()}" for name, cell in
                             zip(COLUMNS[1:], cells[1:]) if cell.text()] + [KEYS_TIP])
            for column, cell in enumerate(cells):
                if why:
                    cell.setForeground(Qt.GlobalColor.gray)
                cell.setToolTip(tip)   # every score, whichever columns the width shows
                table.setItem(row, column, cell)
        table.setSortingEnabled(True)
        table.fit_columns()
        for row in range(table.rowCount()):
            if self._frame_at(row) == kept:
                table.setCurrentCell(row, 2)
        missing = [score for score, _ in rows if (number, score.frame_idx) not in self._asked]
        if missing:
            self._asked.update((number, score.frame_idx) for score in missing)
            self.thumbnails_wanted.emit(missing)

    # ----- what the user does
    def _frame_at(self, row: int) -> int | None:
        item = self.table.item(row, 2)
        return None if item is None else int(item.data(ROLE_FRAME))

    def _choose(self, row: int) -> None:
        frame, number = self._frame_at(row), self.current_animal()
        if frame is not None and number is not None:
            self.frame_chosen.emit(number, frame)

    def _on_key(self, key: int) -> None:
        row, number = self.table.currentRow(), self.current_animal()
        frame = self._frame_at(row) if row >= 0 else None
        if frame is None or number is None:
            return
        if key == Qt.Key.Key_Delete:
            self.reject_toggled.emit(number, frame)
        else:
            self.frame_chosen.emit(number, frame)
