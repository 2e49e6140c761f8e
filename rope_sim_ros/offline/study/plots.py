# Copyright 2026 rope_sim_ros contributors
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

"""
A study's plots: what a newcomer reads at once.

- utilisation.png: for each factor, every case's largest line utilisation (the most loaded
  line's largest tension over its MBL, in %) against that factor's value, the worst case at
  each value joined up, a parted line marked with a red cross, the working load limit and
  the MBL drawn across;
- heatmap.png (two factors or more): the worst case's largest utilisation over two factors
  (the study's `heatmap`, else its first two), each cell naming the line that governs it
  (and saying so when a line parted in one of its cases), the working load limit drawn as
  a contour through the cells; with one factor more, a map for each of its values side by
  side (with more, the worst case over them).

Failed cases are left out (the titles say how many). Matplotlib without a display (Agg).
"""

import math
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

from .file import CASE_FILES, format_value, Study
from .results import OK

UTILISATION_PNG = 'utilisation.png'
HEATMAP_PNG = 'heatmap.png'


def _label(name: str, value: Any) -> str:
    if name in CASE_FILES and isinstance(value, str):
        return os.path.splitext(os.path.basename(value))[0]
    if isinstance(value, float):
        return f'{value:g}'
    return format_value(value)


def _numeric(values: Sequence[Any]) -> bool:
    return all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values)


def worst(row: Mapping[str, Any], lines: Sequence[str]) -> Tuple[float, str, bool]:
    """Return a result row's largest utilisation, the line it is on, and whether any parted."""
    best, where = -math.inf, ''
    parted = False
    for line in lines:
        value = row.get(f'{line}_max_utilisation')
        if value is not None and value > best:
            best, where = value, line
        parted = parted or bool(row.get(f'{line}_parted'))
    return best, where, parted


def _levels(study: Study, name: str, rows: Sequence[Mapping[str, Any]]) -> List[Any]:
    if study.factorial:
        values = list(study.levels[name])
    else:
        values = []
        for row in rows:
            if name in row and row[name] not in values:
                values.append(row[name])
    if _numeric(values):
        values = sorted(set(values), key=float)
    return values


def load_matplotlib():
    """Import matplotlib's pyplot on the Agg backend (no display) and return it."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    return plt


def plot_study(folder, study: Study, rows: Sequence[Mapping[str, Any]], lines: Sequence[str],
               wll_fraction: Optional[float] = None) -> List[str]:
    """
    Draw utilisation.png and (with two factors or more) heatmap.png into the folder.

    :param rows: the result rows (results.py result_rows).
    :param wll_fraction: the smallest WLL / MBL of the lines (drawn across), or None.
    :returns: the files written.
    """
    plt = load_matplotlib()
    folder = os.fspath(folder)
    ok = [row for row in rows if row.get('status') == OK]
    failed = len(rows) - len(ok)
    title = os.path.splitext(os.path.basename(study.path))[0]
    gone = f'; {failed} failed case{"s" if failed != 1 else ""} not shown' if failed else ''
    written = []

    factors = list(study.factors) or ['case']
    count = len(factors)
    columns = min(3, count)
    rows_of_plots = int(math.ceil(count / columns))
    figure, axes = plt.subplots(rows_of_plots, columns, squeeze=False,
                                figsize=(5.0 * columns, 3.8 * rows_of_plots + 0.6))
    for k, name in enumerate(factors):
        axis = axes[k // columns][k % columns]
        values = _levels(study, name, ok) if name != 'case' else [row['case'] for row in ok]
        numeric = _numeric(values)
        position = {format_value(v): (float(v) if numeric else i) for i, v in enumerate(values)}
        xs, ys, parted_x, parted_y = [], [], [], []
        envelope: Dict[float, float] = {}
        for row in ok:
            if name not in row:
                continue
            x = position[format_value(row[name])]
            utilisation, _, parted = worst(row, lines)
            xs.append(x)
            ys.append(100.0 * utilisation)
            envelope[x] = max(envelope.get(x, -math.inf), 100.0 * utilisation)
            if parted:
                parted_x.append(x)
                parted_y.append(100.0 * utilisation)
        axis.plot(xs, ys, 'o', color='tab:blue', alpha=0.5, label='a case')
        if envelope:
            keys = sorted(envelope)
            axis.plot(keys, [envelope[x] for x in keys], '-', color='tab:blue', lw=1.5,
                      label='worst case')
        if parted_x:
            axis.plot(parted_x, parted_y, 'x', color='red', ms=9, mew=2, label='a line parted')
        if wll_fraction is not None:
            axis.axhline(100.0 * wll_fraction, color='orange', ls='--', lw=1,
                         label=f'WLL ({100.0 * wll_fraction:g} % of MBL)')
        axis.axhline(100.0, color='red', ls='-', lw=1, label='MBL')
        if not numeric:
            axis.margins(x=0.2)
            axis.set_xticks(range(len(values)))
            axis.set_xticklabels([_label(name, v) for v in values], rotation=20, ha='right')
        axis.set_xlabel(name)
        axis.set_ylabel('largest line utilisation [% of MBL]')
        axis.set_ylim(bottom=0.0)
        axis.grid(True, alpha=0.3)
        if k == 0:
            axis.legend(fontsize='small', loc='best')
    for k in range(count, rows_of_plots * columns):
        axes[k // columns][k % columns].axis('off')
    figure.suptitle(f'{title}: the most loaded line of each case ({len(ok)} cases{gone})')
    figure.tight_layout()
    path = os.path.join(folder, UTILISATION_PNG)
    figure.savefig(path, dpi=100)
    plt.close(figure)
    written.append(path)

    pair = study.heatmap or (tuple(study.factors[:2]) if len(study.factors) >= 2 else None)
    if pair is not None:
        written.append(_heatmap(plt, folder, study, rows, lines, pair, title, gone,
                                wll_fraction))
    return written


def _heatmap(plt, folder: str, study: Study, rows: Sequence[Mapping[str, Any]],
             lines: Sequence[str], pair: Tuple[str, str], title: str, gone: str,
             wll_fraction: Optional[float] = None) -> str:
    import numpy as np

    across, down = pair
    xs, ys = _levels(study, across, rows), _levels(study, down, rows)
    others = [name for name in study.factors if name not in pair]
    # one more factor: a map for each of its values; more: the worst case over them
    panels = _levels(study, others[0], rows) if len(others) == 1 else [None]
    figure, axes = plt.subplots(1, len(panels), squeeze=False, figsize=(
        max(6.0, (1.1 * len(xs) + 1.2) * len(panels) + 1.8), max(4.0, 0.8 * len(ys) + 2.0)))
    cmap = plt.get_cmap('RdYlGn_r').with_extremes(bad='lightgrey')
    fontsize = 'small' if len(panels) == 1 else 'x-small'
    for axis, value in zip(axes[0], panels):
        chosen = rows if value is None else [
            row for row in rows if others[0] in row
            and format_value(row[others[0]]) == format_value(value)]
        grid, labels = _heat_grid(chosen, lines, across, down, xs, ys)
        image = axis.imshow(np.ma.masked_invalid(grid), cmap=cmap, vmin=0.0, vmax=100.0,
                            aspect='auto', origin='lower')
        for (i, j), text in labels.items():
            axis.text(j, i, text, ha='center', va='center', fontsize=fontsize)
        known = grid[np.isfinite(grid)]
        if wll_fraction is not None and min(grid.shape) >= 2 and known.size and \
                known.min() < 100.0 * wll_fraction < known.max():
            level = 100.0 * wll_fraction
            contour = axis.contour(np.ma.masked_invalid(grid), levels=[level], colors='black',
                                   linewidths=2.0, linestyles='--')
            axis.clabel(contour, fmt={level: f'WLL {level:g} %'}, fontsize=fontsize)
        axis.set_xticks(range(len(xs)))
        axis.set_xticklabels([_label(across, v) for v in xs], rotation=20, ha='right')
        axis.set_yticks(range(len(ys)))
        axis.set_yticklabels([_label(down, v) for v in ys])
        axis.set_xlabel(across)
        axis.set_ylabel(down)
        if value is not None:
            axis.set_title(f'{others[0]} = {_label(others[0], value)}', fontsize='medium')
    figure.colorbar(image, ax=list(axes[0]), label='largest line utilisation [% of MBL]')
    over = f', worst over {", ".join(others)}' if len(others) > 1 else ''
    wll = ('; dashed: the working load limit' if wll_fraction is not None else '')
    figure.suptitle(f'{title}: the most loaded line{over}{wll}{gone}', fontsize='medium')
    path = os.path.join(folder, HEATMAP_PNG)
    figure.savefig(path, dpi=100, bbox_inches='tight')
    plt.close(figure)
    return path


def _heat_grid(rows: Sequence[Mapping[str, Any]], lines: Sequence[str], across: str,
               down: str, xs: Sequence[Any], ys: Sequence[Any]):
    """Return one map's grid of the worst utilisation [%] and each cell's text."""
    import numpy as np

    column = {format_value(v): i for i, v in enumerate(xs)}
    row_of = {format_value(v): i for i, v in enumerate(ys)}
    grid = np.full((len(ys), len(xs)), np.nan)
    governing: Dict[Tuple[int, int], str] = {}
    parted_cells = set()
    for row in rows:
        if row.get('status') != OK or across not in row or down not in row:
            continue
        i, j = row_of[format_value(row[down])], column[format_value(row[across])]
        utilisation, line, parted = worst(row, lines)
        if np.isnan(grid[i, j]) or 100.0 * utilisation > grid[i, j]:
            grid[i, j] = 100.0 * utilisation
            governing[(i, j)] = line
        if parted:
            parted_cells.add((i, j))
    labels = {(i, j): f'{grid[i, j]:.0f} %\n{line}'
              + ('\na line parted' if (i, j) in parted_cells else '')
              for (i, j), line in governing.items()}
    for row in rows:  # a cell whose every case failed says so
        if row.get('status') != OK and across in row and down in row:
            i, j = row_of[format_value(row[down])], column[format_value(row[across])]
            labels.setdefault((i, j), 'failed')
    return grid, labels
