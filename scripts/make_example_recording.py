"""Rewrite the example force-plate recording that ships with viscontact.

    python3 scripts/make_example_recording.py [--out FILE]

See :mod:`viscontact.fit.synthetic` for what it contains (a synthetic Jian impact at the
indoor lacrosse ball's parameters, 50 kHz, 1 % noise, a baseline offset).
"""

from viscontact.fit.synthetic import main

if __name__ == "__main__":
    main()
