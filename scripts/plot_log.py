#!/usr/bin/python3
"""Plots logged channels of one or more runs against simulated time (docs/batch.md, "Plotting logs").

    scripts/plot_log.py RUN [RUN...] --channel REGEX [--channel REGEX]... [--job ID] [--set K]
                        [--by channel|unit] [--out FILE.png] [--title TEXT]

A RUN is a CSV log (docs/formats.md, "CSV logs": `orcs-sim --log ... --out FILE.csv`, or one of an orcs-batch
folder's DIR/logs/*.csv), or a folder holding logs: an orcs-batch run or sweep folder (DIR/logs/), its logs/
folder itself, or an orcs-batch evolve folder (DIR/best/logs/; the winner's replay unless --job names another).
In a folder, --job picks the job (needed when it logged more than one); a job with several parameter sets is one
line per set, or only set K with --set K.

--channel is a Python regular expression searched in each column name (anchor it with ^ and $ to match whole
paths); repeat it for more. Every matching column is one panel (--by unit: one panel per unit), every run one
line in each panel, in its own colour, named in the legend below the panels. The x axis is the simulated time in
seconds; the y axis names the channel and its unit where the repository's path says it (JointAngle: deg,
Position: m, MotorTorque: N·m, ...).

Writes --out (default: log.png in the current folder). Bad input is one line naming the file (and line or
field) on stderr and exit 2; a --channel that matches no column lists the closest column names.
Debian's python3-matplotlib; runs headless.
"""
import argparse
import csv
import difflib
import glob
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after choosing the headless backend)

PROGRAM = "plot_log.py"
MAX_PANELS = 12
COLUMNS_KEY = "columns:"
TRUNCATED = re.compile(r"log truncated at time (\S+) s")
# Units of repository values by the path's last element (model/aseries/aseries_agent.h, model/scene/world_model.h,
# docs/model.md); a vector's component suffix (.x .y .z, .w) is removed first.
UNITS = {
    "Position": "m",
    "Orientation": "deg",  # Euler angles
    "OrientationQuaternion": "unit quaternion",
    "JointAngle": "deg",
    "DesiredAngle": "deg",
    "MinAngle": "deg",
    "MaxAngle": "deg",
    "CurrentVelocity": "rad/s",
    "MotorTorque": "N·m",
    "DesiredTorque": "fraction of max torque",
    "AccelAxis1": "m/s²",
    "AccelAxis2": "m/s²",
    "CurrentSimulationTime": "s",
    "Mass": "kg",
}
LINESTYLES = ["-", "--", ":", "-."]


class InputProblem(Exception):
    """Bad input: the message names the file (and line or field)."""


def fail(message):
    print(f"{PROGRAM}: {message}", file=sys.stderr)
    sys.exit(2)


def unit_of(channel):
    """The unit of a column name, or None when the path does not say."""
    name = channel.rsplit("/", 1)[-1]
    base = re.sub(r"\.[xyzwrgba]$", "", name)
    return UNITS.get(base)


def short_name(channel):
    """The last two path elements (Right/Knee/JointAngle → Knee/JointAngle), for axis labels."""
    parts = channel.strip("/").split("/")
    return "/".join(parts[-2:])


class Log:
    """One CSV log: its comments' facts, its column names and, after `load`, the chosen columns as floats."""

    def __init__(self, path):
        self.path = path
        self.facts = {}  # "scenario", "environment", "seed", "parameter set", ... from the leading comments
        self.columns = None
        self.columns_line = None
        self.truncated_at = None
        self.data = {}  # column → list of floats
        self._read_header()

    def _lines(self):
        try:
            handle = open(self.path, newline="", encoding="utf-8-sig")
        except OSError as error:
            raise InputProblem(f"{self.path}: {error.strerror}")
        with handle:
            try:
                for number, line in enumerate(handle, start=1):
                    yield number, line.rstrip("\r\n")
            except UnicodeDecodeError:
                raise InputProblem(f"{self.path}: not a text file (not UTF-8)")

    def _note_comment(self, number, line):
        body = line.lstrip("#").strip()
        if body.lower().startswith(COLUMNS_KEY):
            if self.columns is not None:
                raise InputProblem(f"{self.path}:{number}: a second '# columns:' comment (the first is on line "
                                   f"{self.columns_line})")
            self.columns = [c.strip() for c in body[len(COLUMNS_KEY):].split(",")]
            self.columns_line = number
            if self.columns[0] != "time":
                raise InputProblem(f"{self.path}:{number}: the first column must be 'time', found "
                                   f"{self.columns[0]!r}")
            if len(set(self.columns)) != len(self.columns):
                raise InputProblem(f"{self.path}:{number}: a column is named twice")
            return
        truncated = TRUNCATED.search(body)
        if truncated:
            self.truncated_at = truncated.group(1)
        elif ":" in body and self.columns is None:
            key, value = body.split(":", 1)
            self.facts[key.strip()] = value.strip()

    def _read_header(self):
        for number, line in self._lines():
            if not line.strip():
                continue
            if line.lstrip().startswith("#"):
                self._note_comment(number, line)
                if self.columns is not None:
                    return
            else:
                raise InputProblem(f"{self.path}:{number}: a data row before the '# columns:' comment (not an "
                                   "orcs log? orcs-sim --log and orcs-batch write one)")
        raise InputProblem(f"{self.path}: no '# columns:' comment naming the columns (not an orcs log?)")

    def load(self, wanted):
        """Reads time and the wanted columns as floats. A column whose first value is not a number is text (a
        string value such as a material): it is dropped and returned; a later non-number in a numeric column is
        an error naming the line and column."""
        index = {c: i for i, c in enumerate(self.columns)}
        wanted = [c for c in wanted if c in index]
        self.data = {c: [] for c in ["time"] + wanted}
        text_columns = set()
        rows = 0
        for number, line in self._lines():
            if number <= self.columns_line or not line.strip():
                continue
            if line.lstrip().startswith("#"):
                self._note_comment(number, line)
                continue
            fields = next(csv.reader([line]))
            if len(fields) != len(self.columns):
                raise InputProblem(f"{self.path}:{number}: expected {len(self.columns)} fields (the '# columns:' "
                                   f"of line {self.columns_line}), found {len(fields)}")
            for column in self.data:
                if column in text_columns:
                    continue
                text = fields[index[column]].strip()
                try:
                    self.data[column].append(float(text))
                except ValueError:
                    if rows == 0 and column != "time":
                        text_columns.add(column)
                        continue
                    raise InputProblem(f"{self.path}:{number}: column {column}: expected a number, found {text!r}")
            rows += 1
        if rows == 0:
            raise InputProblem(f"{self.path}: no data rows")
        for column in text_columns:
            del self.data[column]
        return sorted(text_columns, key=index.get)

    def scenario(self):
        if "scenario" in self.facts:
            return self.facts["scenario"]
        if "environment" in self.facts:
            return os.path.splitext(os.path.basename(self.facts["environment"]))[0]
        return None


def job_logs(folder):
    """{job id: [(set index or None, path)]} of the CSV logs in a logs folder."""
    jobs = {}
    for path in sorted(glob.glob(os.path.join(glob.escape(folder), "*.csv"))):
        name = os.path.basename(path)[:-4]
        match = re.fullmatch(r"(.+)\.set-(\d+)", name)
        job, index = (match.group(1), int(match.group(2))) if match else (name, None)
        jobs.setdefault(job, []).append((index, path))
    for entries in jobs.values():
        entries.sort(key=lambda entry: -1 if entry[0] is None else entry[0])
    return jobs


def logs_folder(run):
    for candidate in (os.path.join(run, "logs"), os.path.join(run, "best", "logs"), run):
        if os.path.isdir(candidate) and glob.glob(os.path.join(glob.escape(candidate), "*.csv")):
            return candidate
    raise InputProblem(f"{run}: no CSV logs in it, in {os.path.join(run, 'logs')} or in "
                       f"{os.path.join(run, 'best', 'logs')} (does the scenario have a \"log\"?)")


def close_names(wanted, names, count=5):
    """The names most like `wanted`, in their own order."""
    near = set(difflib.get_close_matches(wanted, names, n=count, cutoff=0.5))
    return [n for n in names if n in near]


def logs_of_run(run, job, parameter_set):
    """(job id or None for a file, [(set index or None, path)]) of one RUN argument."""
    if not os.path.exists(run):
        raise InputProblem(f"{run}: no such file or folder")
    if not os.path.isdir(run):  # a file; one in a logs folder names its job and set
        match = re.fullmatch(r"(.+?)(?:\.set-(\d+))?\.csv", os.path.basename(run))
        if match and os.path.basename(os.path.dirname(os.path.abspath(run))) == "logs":
            return match.group(1), [(int(match.group(2)) if match.group(2) else None, run)]
        return None, [(None, run)]
    folder = logs_folder(run)
    jobs = job_logs(folder)
    if job is None and "winner" in jobs:  # an evolve folder: the winner's replay, not its validation runs
        job = "winner"
    if job is None:
        if len(jobs) > 1:
            names = sorted(jobs)
            shown = ", ".join(names[:8]) + (f", ... ({len(names)} jobs)" if len(names) > 8 else "")
            raise InputProblem(f"{folder}: logs of {len(jobs)} jobs ({shown}): choose one with --job")
        job = next(iter(jobs))
    if job not in jobs:
        near = close_names(job, sorted(jobs)) or sorted(jobs)[:5]
        raise InputProblem(f"{folder}: no log of job {job!r}; it has {', '.join(near)}"
                           + (" ..." if len(jobs) > len(near) else ""))
    entries = jobs[job]
    if parameter_set is not None:
        chosen = [e for e in entries if e[0] == parameter_set or (e[0] is None and parameter_set == 0)]
        if not chosen:
            have = ", ".join("0" if e[0] is None else str(e[0]) for e in entries)
            raise InputProblem(f"{folder}: job {job} has no log of parameter set {parameter_set} (sets {have})")
        entries = chosen
    return job, entries


def run_labels(runs):
    """Legend names of the RUN arguments: their last path element, or the whole path when two would clash."""
    def base(run):
        name = os.path.basename(os.path.normpath(run))
        return name[:-4] if name.endswith(".csv") else name
    labels = [base(run) for run in runs]
    if len(set(labels)) < len(labels):
        labels = [os.path.normpath(run) for run in runs]
    return labels


def select_channels(logs, patterns):
    """The columns any pattern finds, in the order of the patterns (and of the logs' columns for one pattern);
    raises naming the closest columns when a pattern finds none."""
    names = []
    for log in logs:
        for column in log.columns[1:]:
            if column not in names:
                names.append(column)
    compiled = []
    for pattern in patterns:
        try:
            compiled.append(re.compile(pattern))
        except re.error as error:
            raise InputProblem(f"--channel {pattern!r}: not a regular expression: {error}")
    chosen = []
    for pattern, expression in zip(patterns, compiled):
        found = [n for n in names if expression.search(n)]
        if not found:
            raise InputProblem(unknown_channel_message(pattern, names, logs))
        chosen.extend(n for n in found if n not in chosen)
    return chosen


def unknown_channel_message(pattern, names, logs):
    """Names the logs and the columns closest to the pattern (whole names, then their last path elements)."""
    plain = re.sub(r"[\\^$.*+?()\[\]{}|]", "", pattern)
    near = close_names(pattern, names) or close_names(plain, names)
    if not near:
        tails = {}
        for n in names:
            parts = n.split("/")
            for k in range(1, min(4, len(parts)) + 1):
                tails.setdefault("/".join(parts[-k:]), n)
        near = [tails[t] for t in close_names(plain, list(tails), count=8)]
        near = list(dict.fromkeys(near))[:5]
    where = logs[0].path if len(logs) == 1 else f"{logs[0].path} (and {len(logs) - 1} more logs)"
    if near:
        return f"--channel {pattern!r}: no column of {where} matches; close: {', '.join(near)}"
    shown = ", ".join(names[:6]) + (", ..." if len(names) > 6 else "")
    return f"--channel {pattern!r}: no column of {where} matches; the log has {shown}"


def panels_of(channels, by):
    """[(panel key, [channels])]: one per channel, or one per unit (a channel without a known unit alone)."""
    if by == "channel":
        return [(c, [c]) for c in channels]
    groups = {}
    for c in channels:
        groups.setdefault(unit_of(c) or c, []).append(c)
    return list(groups.items())


def title_of(lines, channels, patterns, job):
    if job is None:  # the job of folder runs, when they all show the same one
        jobs = {line.get("job") for line in lines}
        job = jobs.pop() if len(jobs) == 1 else None
    scenarios = list(dict.fromkeys(s for s in (line["log"].scenario() for line in lines) if s))
    what = " vs ".join(scenarios) if scenarios else "log"
    if job:
        what += f", {job}"
    if len(channels) <= 3:
        measured = ", ".join(short_name(c) for c in channels)
    else:
        measured = f"{len(channels)} channels matching " + " or ".join(repr(p) for p in patterns)
    return f"{what}: {measured}"


def build_figure(lines, channels, patterns, by="channel", title=None, job=None):
    """lines: [{"label", "run" (index), "set" (index or None), "log" (a loaded Log), "job"}]. Returns the figure: one
    panel per channel (or unit), sharing the time axis, one legend below the panels."""
    panels = panels_of(channels, by)
    if len(panels) > MAX_PANELS:
        raise InputProblem(f"--channel: {len(panels)} panels ({len(channels)} channels) are too many to read; at "
                           f"most {MAX_PANELS}: narrow the expressions or use --by unit")
    runs = sorted({line["run"] for line in lines})
    per_channel_colours = by == "unit" and any(len(members) > 1 for _, members in panels)
    legend_rows = math.ceil(len(lines) / 3) if not per_channel_colours else 0
    height = 2.3 * len(panels) + 0.9 + 0.28 * legend_rows
    figure, axes = plt.subplots(len(panels), 1, figsize=(9, height), sharex=True, squeeze=False)
    axes = axes[:, 0]
    handles = {}
    for axis, (key, members) in zip(axes, panels):
        for k, channel in enumerate(members):
            for line in lines:
                data = line["log"].data
                if channel not in data:
                    continue
                name = line["label"]
                if line["log"].truncated_at is not None:
                    name += f" (log truncated at {line['log'].truncated_at} s)"
                style = LINESTYLES[(line["set"] or 0) % len(LINESTYLES)] if len(runs) > 1 else "-"
                if per_channel_colours:
                    colour, label = f"C{k % 10}", f"{short_name(channel)}, {name}"
                    style = LINESTYLES[(runs.index(line["run"]) * 2 + (line["set"] or 0)) % len(LINESTYLES)]
                elif len(runs) > 1:
                    colour, label = f"C{runs.index(line['run']) % 10}", name
                else:  # one run: a colour per parameter set
                    colour, label = f"C{(line['set'] or 0) % 10}", name
                # earlier runs drawn wider, so that a later run on top of them leaves them visible
                width = 1.0 + 0.5 * (len(runs) - 1 - runs.index(line["run"]))
                drawn, = axis.plot(data["time"], data[channel], style, color=colour, linewidth=width, label=label)
                handles.setdefault(label, drawn)
        unit = unit_of(members[0])
        if len(members) == 1:
            axis.set_title(members[0], fontsize="medium", loc="left")
            axis.set_ylabel(short_name(members[0]) + (f" ({unit})" if unit else ""))
        else:
            axis.set_title(", ".join(short_name(c) for c in members), fontsize="medium", loc="left")
            axis.set_ylabel(unit if unit else key)
            axis.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
        axis.grid(True, alpha=0.3)
    axes[-1].set_xlabel("simulated time (s)")
    figure.suptitle(title or title_of(lines, channels, patterns, job))
    bottom = 0.0
    if not per_channel_colours:
        bottom = (0.25 * legend_rows + 0.08) / height
        figure.legend(list(handles.values()), list(handles), loc="lower center", ncol=min(3, len(handles)),
                      fontsize="small", frameon=False, bbox_to_anchor=(0.5, 0.0))
    figure.tight_layout(rect=(0, bottom, 1, 1))
    return figure


def gather(runs, job, parameter_set):
    """Reads the RUN arguments' logs (their headers): [{"label", "run", "set", "log", "job"}]."""
    lines = []
    for number, (run, label) in enumerate(zip(runs, run_labels(runs))):
        job_id, entries = logs_of_run(run, job, parameter_set)
        for index, path in entries:
            log = Log(path)
            name = label
            if len(entries) > 1 and index is not None:
                name += f", set {index}"
            lines.append({"label": name, "run": number, "set": index, "log": log, "job": job_id})
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(prog=PROGRAM, description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", metavar="RUN",
                        help="a CSV log, or a folder with logs (orcs-batch --out DIR, DIR/logs, an evolve DIR)")
    parser.add_argument("--channel", action="append", required=True, metavar="REGEX",
                        help="regular expression searched in the column names (repeatable)")
    parser.add_argument("--job", help="in a folder, the job whose logs are plotted (e.g. job-0)")
    parser.add_argument("--set", type=int, dest="parameter_set", metavar="K",
                        help="only parameter set K of a job (default: every set, one line each)")
    parser.add_argument("--by", choices=["channel", "unit"], default="channel",
                        help="one panel per channel (default) or per unit")
    parser.add_argument("--out", default="log.png", help="the PNG to write (default log.png)")
    parser.add_argument("--title", help="the figure's title (default: scenario, job and channels)")
    arguments = parser.parse_args(argv)
    try:
        lines = gather(arguments.runs, arguments.job, arguments.parameter_set)
        channels = select_channels([line["log"] for line in lines], arguments.channel)
        for line in lines:
            text = line["log"].load(channels)
            for column in text:
                print(f"{PROGRAM}: {line['log'].path}: column {column} holds text, not numbers; left out",
                      file=sys.stderr)
        channels = [c for c in channels if any(c in line["log"].data for line in lines)]
        if not channels:
            raise InputProblem(f"--channel: the matching columns of {lines[0]['log'].path} hold text, not numbers")
        figure = build_figure(lines, channels, arguments.channel, arguments.by, arguments.title, arguments.job)
    except InputProblem as problem:
        fail(str(problem))
    out_folder = os.path.dirname(os.path.abspath(arguments.out))
    if not os.path.isdir(out_folder):
        fail(f"{arguments.out}: no folder {out_folder}")
    temporary = f"{arguments.out}.tmp.{os.getpid()}.png"
    figure.savefig(temporary, dpi=110)
    plt.close(figure)
    os.replace(temporary, arguments.out)
    print(f"{PROGRAM}: wrote {arguments.out}")


if __name__ == "__main__":
    main()
