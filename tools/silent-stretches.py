#!/usr/bin/python3
"""Runs a command on a pseudo-terminal (so vpsim draws its progress lines) and lists the stretches
of at least MIN_GAP seconds (default 2) in which nothing reached the terminal: neither a progress
redraw nor a log line. Before them, a timeline of the lines shown, one per progress label.

    tools/silent-stretches.py build/vpsim run examples/seed001-holes.json --out out/holes

Issue 24 item 6: every stage that can take more than a few seconds reports progress."""
import os
import pty
import re
import sys
import time

MIN_GAP = float(os.environ.get("MIN_GAP", "2"))


def main(command):
    pid, fd = pty.fork()
    if pid == 0:
        os.execvp(command[0], command)
    start = last = time.time()
    last_text, pending, gaps, timeline = "(start)", b"", [], [(0.0, "(start)", "")]
    while True:
        try:
            data = os.read(fd, 4096)
        except OSError:  # the child closed the terminal
            break
        if not data:
            break
        now = time.time()
        shown = pending.decode(errors="replace").strip()
        pieces = re.split(rb"[\r\n]", pending + data)
        pending = pieces[-1]
        # The unterminated piece is on the screen already (a progress line ends with the next
        # redraw's carriage return), so it counts when it arrives, not again when it ends.
        texts = [p.decode(errors="replace").strip() for p in pieces]
        if shown and texts[0] == shown:
            texts = texts[1:]
        texts = [t for t in texts if t]
        if not texts:
            continue
        if now - last >= MIN_GAP:
            gaps.append((now - last, last - start, last_text, texts[0]))
        for text in texts:
            # A progress line is redrawn in place: one timeline entry per label.
            key = text.split(":")[0] if ("%" in text or " done, " in text) else text
            if key == timeline[-1][1]:
                timeline[-1] = (timeline[-1][0], key, text)
            else:
                timeline.append((now - start, key, text))
        last, last_text = now, texts[-1]
    now = time.time()
    if now - last >= MIN_GAP:
        gaps.append((now - last, last - start, last_text, "(end)"))
    _, status = os.waitpid(pid, 0)
    for at, _, text in timeline[1:]:
        print(f"{at:7.1f} s  {text[:110]}")
    print(f"total {now - start:.1f} s, exit status {os.waitstatus_to_exitcode(status)}; "
          f"silent stretches >= {MIN_GAP:g} s: {len(gaps)}")
    for gap, at, before, after in gaps:
        print(f"  {gap:6.1f} s from {at:6.1f} s  after: {before[:90]!r}\n"
              f"{'':25}until: {after[:90]!r}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
