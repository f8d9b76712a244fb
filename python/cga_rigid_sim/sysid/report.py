"""The fit's report: a Markdown table, the results as JSON, and plots (matplotlib, Agg)."""
import json
import os

import numpy as np


def _fmt_params(p):
    return ', '.join('%s = %.4g' % (k, v) for k, v in p.items())


def write(out_dir, summary, details=None):
    """report.md and results.json in out_dir (None: nothing written); returns the Markdown."""
    lines = ['# Fit report', '',
             'Data: %s (%d runs), URDF: %s, body %s, size %.4g m, dt %.6g s, %s.' % (
                 summary['data'], summary['runs'], summary['urdf'], summary['body'],
                 summary['size'], summary['dt'], summary['runner']),
             'Parameters fitted: %s.' % ', '.join(
                 '%s in [%g, %g]' % (n, lo, hi) for n, (lo, hi) in summary['ranges'].items()),
             '', '| model | fold | fitted on | tested on | fitted values | train position | '
             'train rotation | test position | test rotation | evaluations |',
             '|---|---|---|---|---|---|---|---|---|---|']
    for f in summary['folds']:
        row = '| %s | %d | %s | %s | %s | %.1f %% | %.1f° | %.1f %% ± %.1f | %.1f° ± %.1f | %d |'
        lines.append(row % (
            f['model'], f['fold'], f['train_runs'], f['test_runs'], _fmt_params(f['params']),
            100 * f['train']['position'], f['train']['rotation_deg'],
            100 * f['test']['position_mean'], 100 * f['test']['position_std'],
            f['test']['rotation_mean_deg'], f['test']['rotation_std_deg'], f['evaluations']))
    # One fold (--folds 1) fits on every run and tests on the same: not held out.
    which = ('the runs it was fitted on (in sample, not held out)' if summary.get('in_sample')
             else 'held-out runs of every fold together')
    for m in summary.get('models', []):
        lines.append('')
        lines.append('**%s**, %s: position %.1f %% ± %.1f of '
                     'the size, rotation %.1f° ± %.1f (%d runs).' % (
                         m['model'], which, 100 * m['position_mean'], 100 * m['position_std'],
                         m['rotation_mean_deg'], m['rotation_std_deg'], m['runs']))
    failed = [x for f in summary['folds'] for x in f.get('failed', [])]
    lines.append('')
    if failed:
        lines.append('Failed simulations (%d), reported with their parameters:' % len(failed))
        for x in failed[:50]:
            lines.append('- run %s, %s: %s' % (x['run'], _fmt_params(x['params']), x['error']))
    else:
        lines.append('No simulation failed.')
    if summary.get('plots'):
        lines.append('')
        for title, name in summary['plots']:
            lines.append('![%s](%s)' % (title, name))
    text = '\n'.join(lines) + '\n'
    if out_dir is None:
        return text
    os.makedirs(out_dir, exist_ok=True)
    with open(os.path.join(out_dir, 'report.md'), 'w') as f:
        f.write(text)
    with open(os.path.join(out_dir, 'results.json'), 'w') as f:
        json.dump({'summary': summary, 'details': details or {}}, f, indent=1, default=float)
    return text


def plot_errors(path, per_model, runs_are='held-out run'):
    """Per held-out run (or `runs_are`): position and rotation error, one series per model."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
    for name, rows in per_model.items():
        runs = [r['run'] for r in rows]
        x = np.arange(len(runs))
        ax[0].plot(x, [100 * r['position'] for r in rows], '.', label=name)
        ax[1].plot(x, [np.degrees(r['rotation']) for r in rows], '.', label=name)
    ax[0].axhline(10, color='k', lw=0.5, ls='--')
    ax[1].axhline(15, color='k', lw=0.5, ls='--')
    ax[0].set_ylabel('position error, % of size')
    ax[1].set_ylabel('rotation error, deg')
    ax[1].set_xlabel('%s (in data order)' % runs_are)
    ax[0].legend(fontsize=8)
    ax[0].set_title('Mean error per %s (dashed: 10 %% and 15°)' % runs_are)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_error_vs_time(path, per_model, rate):
    """Mean error over held-out runs against time since the start."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.6))
    for name, rows in per_model.items():
        n = max(len(r['position_series']) for r in rows)
        for k, key, scale in ((0, 'position_series', 100.0), (1, 'rotation_series', 180 / np.pi)):
            acc = np.full((len(rows), n), np.nan)
            for i, r in enumerate(rows):
                acc[i, :len(r[key])] = scale * r[key]
            ax[k].plot(np.arange(n) / rate, np.nanmean(acc, axis=0), label=name)
    ax[0].set_ylabel('position error, % of size')
    ax[1].set_ylabel('rotation error, deg')
    for a in ax:
        a.set_xlabel('time since the start, s')
    ax[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_sensitivity(path, sens_by_model, columns=4):
    """The objective along each fitted parameter about the optimum, a panel per parameter,
    one colour per model."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    names = sorted({n for s in sens_by_model.values() for n in s})
    if not names:
        return
    cols = min(columns, len(names))
    rows = (len(names) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.3 * cols, 2.6 * rows), squeeze=False)
    colours = {m: 'C%d' % k for k, m in enumerate(sens_by_model)}
    for ax, name in zip(axes.flat, names):
        for model, sens in sens_by_model.items():
            if name in sens:
                v, j = zip(*sens[name])
                ax.plot(v, j, 'o-', ms=3, color=colours[model], label=model)
        ax.set_xlabel(name)
        ax.set_ylabel('objective J')
    for ax in list(axes.flat)[len(names):]:
        ax.axis('off')
    handles = [plt.Line2D([], [], color=c, marker='o', label=m) for m, c in colours.items()]
    fig.legend(handles=handles, loc='upper right', fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
