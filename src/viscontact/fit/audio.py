"""Impact times from a sound recording of a bouncing ball (WAV; other formats through ffmpeg).

An impact is a sharp broadband transient (rise well under 1 ms), a ringing decay of a few ms
and the room's reverberation; between impacts there are noise, mains hum and the odd unrelated
click.  :func:`detect_impacts` finds the onsets in four steps (the envelope-and-adaptive-
threshold onset detection of Bello et al., IEEE Trans. Speech Audio Process. 13 (2005) 1035,
sec. III; docs/fit-restitution.md):

1. a zero-phase high-pass (4th order Butterworth at 1 kHz, forward and backward) removes hum
   and rumble without moving the transients in time;
2. the RMS envelope in frames of 0.25 ms is compared with the median envelope of the 2 to
   30 ms before (what the room was doing: noise, reverberation of the last impact) and with
   the recording's median (the noise floor); a rise above ``ratio`` times both is a candidate,
   at most one per ``min_spacing``;
3. the onset (the impact time: not the envelope's peak, which lags by the ring's rise) is
   where the signal first reaches max(30 % of the transient's first peak, 5 noise sigmas),
   interpolated between samples;
4. a candidate that splits one flight into two short ones (an unrelated click) is dropped:
   bounce flights shrink steadily (:func:`viscontact.fit.bounces.reduce_bounces` names the
   glitches that remain).
"""

from __future__ import annotations

import math
import shutil
import subprocess
import wave
from pathlib import Path
from typing import Any

import numpy as np

from ..physics import domain
from ..physics.pair import check_positive
from .recording import RecordingError, check_path, float_array

__all__ = ["read_audio", "detect_impacts", "MAX_SECONDS"]

#: longest recording read [s] (a bouncing ball is silent within a minute)
MAX_SECONDS = 600.0
_HIGHPASS_HZ = 1000.0
_FRAME_S = 0.25e-3
#: sample rates accepted [Hz]: the 1 kHz high-pass needs > 2 kHz; 10 MHz is beyond any recorder
_MIN_RATE, _MAX_RATE = 4000.0, 1e7


def read_audio(path: str | Path) -> tuple[np.ndarray, float]:
    """(mono signal scaled to [-1, 1], sample rate [Hz]) of a recording.

    WAV: mono or several channels (averaged), 8/16/24/32-bit PCM or 32/64-bit float, any rate
    (scipy's reader, the standard library's for what it declines).  Other formats (m4a/AAC,
    mp3, ogg, ...) are decoded by ffmpeg where it is installed; without it one error says how
    to convert.  RecordingError names what is wrong.
    """
    p = check_path(path)
    if not p.is_file():
        raise RecordingError(f"{path}: no such file")
    if p.suffix.lower() in (".wav", ".wave"):
        x, rate = _read_wav(p)
    else:
        x, rate = _decode(p)
    if x.ndim > 1:
        x = x.mean(axis=1)
    if x.size == 0:
        raise RecordingError(f"{path}: the recording is empty")
    if x.size / rate > MAX_SECONDS:
        raise RecordingError(f"{path}: {x.size / rate:.0f} s long; at most {MAX_SECONDS:.0f} s "
                             "are read (cut the recording to the bouncing)")
    if not np.all(np.isfinite(x)):
        raise RecordingError(f"{path}: the recording holds non-finite samples")
    return x, float(rate)


def _read_wav(p: Path) -> tuple[np.ndarray, float]:
    from scipy.io import wavfile

    try:
        with open(p, "rb") as fh:
            head = fh.read(12)
        if head[:4] not in (b"RIFF", b"RF64") or head[8:12] != b"WAVE":
            raise RecordingError(f"{p}: not a WAV file (no RIFF/WAVE header)")
        rate, data = wavfile.read(p, mmap=False)
    except RecordingError:
        raise
    except Exception:  # formats scipy declines: try the standard library's reader
        return _read_wav_stdlib(p)
    return _scale(np.asarray(data)), float(rate)


def _scale(data: np.ndarray) -> np.ndarray:
    """Samples as floats in [-1, 1] (unsigned 8-bit centred; integers by their full scale)."""
    if data.dtype == np.uint8:
        return (data.astype(float) - 128.0) / 128.0
    if np.issubdtype(data.dtype, np.integer):
        return data.astype(float) / float(2 ** (8 * data.dtype.itemsize - 1))
    return data.astype(float)


def _read_wav_stdlib(p: Path) -> tuple[np.ndarray, float]:
    try:
        with wave.open(str(p), "rb") as w:
            rate, width, ch, n = w.getframerate(), w.getsampwidth(), w.getnchannels(), w.getnframes()
            raw = w.readframes(n)
    except (wave.Error, EOFError, OSError) as exc:
        raise RecordingError(f"{p}: cannot read this WAV file ({exc}); allowed are PCM of "
                             "8/16/24/32 bits or 32/64-bit float") from None
    b = np.frombuffer(raw, dtype=np.uint8)
    if width == 3:  # 24-bit little-endian: sign-extend into int32
        b = b[: b.size // 3 * 3].reshape(-1, 3)
        v = (b[:, 0].astype(np.int32) | (b[:, 1].astype(np.int32) << 8)
             | (b[:, 2].astype(np.int32) << 16))
        v = np.where(v >= 1 << 23, v - (1 << 24), v)
        x = v / float(1 << 23)
    else:
        dtype = {1: np.uint8, 2: np.int16, 4: np.int32}.get(width)
        if dtype is None:
            raise RecordingError(f"{p}: {8 * width}-bit samples; allowed are 8/16/24/32 bits")
        x = _scale(np.frombuffer(raw, dtype=np.dtype(dtype).newbyteorder("<")))
    return x.reshape(-1, ch) if ch > 1 else x, float(rate)


def _decode(p: Path) -> tuple[np.ndarray, float]:
    ffmpeg = shutil.which("ffmpeg")
    how = (f"convert it to WAV first, e.g. `ffmpeg -i '{p.name}' '{p.stem}.wav'` (or export "
           "WAV from the recording app or Audacity)")
    if ffmpeg is None:
        raise RecordingError(f"{p}: cannot decode {p.suffix or 'this'} audio here (no ffmpeg "
                             f"found); {how}")
    try:
        run = subprocess.run([ffmpeg, "-v", "error", "-i", str(p), "-f", "f32le", "-ac", "1",
                              "-ar", "48000", "-"], capture_output=True, timeout=120)
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise RecordingError(f"{p}: ffmpeg could not decode it ({exc}); {how}") from None
    if run.returncode != 0:
        msg = run.stderr.decode(errors="replace").strip().splitlines()
        raise RecordingError(f"{p}: ffmpeg could not decode it ({msg[-1] if msg else 'error'}); "
                             f"{how}")
    return np.frombuffer(run.stdout, dtype="<f4").astype(float), 48000.0


def _highpass(x: np.ndarray, rate: float) -> np.ndarray:
    from scipy.signal import butter, sosfiltfilt

    cut = min(_HIGHPASS_HZ, 0.25 * rate)
    sos = butter(2, cut, btype="highpass", fs=rate, output="sos")
    return sosfiltfilt(sos, x)


def detect_impacts(x: Any, rate: float, *, ratio: float = 4.0, min_spacing: float = 0.01,
                   physics: bool = True) -> np.ndarray:
    """Impact onset times [s] in the recording ``x`` sampled at ``rate`` [Hz].

    ``ratio``: how far the envelope must rise above the noise and the room before it;
    ``min_spacing`` [s]: the shortest time between two impacts; ``physics``: drop candidates
    that split one flight into two (module docstring, step 4)."""
    from scipy.ndimage import median_filter

    x = float_array("x (the samples)", x)
    if x.ndim != 1:
        raise ValueError(f"x must be one channel (a 1-D array of samples), got shape {x.shape}")
    rate = check_positive("rate", rate)
    if not _MIN_RATE <= rate <= _MAX_RATE:
        raise ValueError(f"rate must be in [{_MIN_RATE:g}, {_MAX_RATE:g}] Hz, got {rate:g}")
    ratio = check_positive("ratio", ratio)
    min_spacing = domain.check_number("min_spacing", min_spacing)
    if not 0.0 <= min_spacing <= MAX_SECONDS:
        raise ValueError(f"min_spacing must be in [0, {MAX_SECONDS:g}] s, got {min_spacing!r}")
    physics = domain.check_bool("physics", physics)
    y = _highpass(x, rate)
    hop = max(1, int(round(rate * _FRAME_S)))
    nf = y.size // hop
    if nf < 8:
        return np.zeros(0)
    env = np.sqrt(np.mean(y[: nf * hop].reshape(nf, hop) ** 2, axis=1))
    floor = float(np.median(env)) + 1e-300
    win, gap = max(3, int(round(28e-3 / _FRAME_S))), max(1, int(round(2e-3 / _FRAME_S)))
    med = median_filter(env, size=win, mode="nearest")
    shift = win // 2 + gap
    room = np.concatenate([np.full(shift, med[0]), med[:-shift]])[:nf]
    level = env / np.maximum(room, floor)
    above = level > ratio
    rises = np.flatnonzero(above & ~np.concatenate([[False], above[:-1]]))
    spacing = max(1, int(round(min_spacing / _FRAME_S)))
    picked: list[int] = []
    for f in rises:
        if not picked or f - picked[-1] >= spacing:
            picked.append(int(f))
    times = np.array([_onset(y, rate, f * hop, hop) for f in picked])
    if physics and times.size >= 4:
        times = _drop_splitting_clicks(times)
    return times


def _onset(y: np.ndarray, rate: float, s0: int, hop: int) -> float:
    """The first crossing of max(0.3 A, 5 sigma) before the transient's peak A, interpolated."""
    n1 = int(round(1.5e-3 * rate))
    lo = max(0, s0 - int(round(1e-3 * rate)))
    seg = np.abs(y[s0: s0 + hop + n1])
    if seg.size == 0:
        return s0 / rate
    peak_i = s0 + int(np.argmax(seg))
    amp = float(np.abs(y[peak_i]))
    quiet = y[max(0, lo - int(round(10e-3 * rate))): lo]
    sigma = float(np.sqrt(np.mean(quiet ** 2))) if quiet.size else 0.0
    thr = max(0.3 * amp, min(5.0 * sigma, 0.9 * amp))
    a = np.abs(y[lo: peak_i + 1])
    k = int(np.argmax(a >= thr))
    if k == 0:
        return (lo + k) / rate
    y0, y1 = a[k - 1], a[k]
    frac = (thr - y0) / (y1 - y0) if y1 > y0 else 1.0
    return (lo + k - 1 + frac) / rate


def _drop_splitting_clicks(t: np.ndarray) -> np.ndarray:
    """Drop onsets that split one flight into two: while some interior onset's two intervals
    sum to nearer the flight expected from its neighbours (rho times the one before) than
    the first of them alone, the worst such onset goes."""
    t = list(t)
    while len(t) >= 4:
        I = np.diff(t)
        if np.any(I <= 0):  # coinciding onsets (min_spacing 0): no ratios to judge by
            break
        r = I[1:] / I[:-1]
        ok = r[(r > 0) & (r < 1)]
        if ok.size == 0:
            break
        rho = float(np.median(ok))
        worst, gain = None, 0.0
        for j in range(1, len(I) - 1):  # onset j + 1 sits between intervals j and j + 1
            prev = I[j - 1]
            alone = abs(math.log(I[j] / prev / rho))
            merged = abs(math.log((I[j] + I[j + 1]) / prev / rho))
            after = abs(math.log(I[j + 1] / I[j] / rho))
            if merged < alone and merged < after and alone - merged > gain:
                worst, gain = j + 1, alone - merged
        if worst is None:
            break
        del t[worst]
    return np.array(t)
