"""Impact times from a recording: a synthetic recording built from known impact times (ringing
transients, white noise 20 dB below the quietest impact's peak, mains hum, one unrelated
click, room reverberation) gives those times to 0.1 ms and the same (v, e) to 1e-3; the WAV
sample formats read alike; bad recordings get one error."""

from __future__ import annotations

import wave

import numpy as np
import pytest
from scipy.io import wavfile
from scipy.signal import fftconvolve

from viscontact.fit.audio import detect_impacts, read_audio
from viscontact.fit.bounces import reduce_bounces
from viscontact.fit.recording import RecordingError
from viscontact.fit.restitution import model_e

RATE = 44100.0
G = 9.81


def bounce_times(u0=3.0, n=10):
    """Drag-free bounces with KK's e(v): impact times and the true (v, e)."""
    t, u, times = 0.0, u0, [0.3]
    for _ in range(n - 1):
        t_fl = 2 * u / G
        times.append(times[-1] + t_fl)
        u = float(model_e("KK", u, 1.0, 0.2)) * u
    return np.array(times)


def synthetic_recording(times, seed=0, click_at=None):
    """The recording: each impact a sum of three decaying modes started at its time (sub-sample
    exact), amplitude ~ impact order; reverb; hum; white noise; one click."""
    rng = np.random.default_rng(seed)
    dur = times[-1] + 0.4
    n = int(dur * RATE)
    ts = np.arange(n) / RATE
    clean = np.zeros(n)
    amps = 0.5 * 0.85 ** np.arange(times.size)
    for tk, a in zip(times, amps):
        i0 = int(np.ceil(tk * RATE))
        s = ts[i0: i0 + int(0.03 * RATE)] - tk
        ring = (np.sin(2 * np.pi * 2700 * s) * np.exp(-s / 3e-3)
                + 0.6 * np.sin(2 * np.pi * 4300 * s + 0.3) * np.exp(-s / 2e-3)
                + 0.4 * np.sin(2 * np.pi * 6100 * s + 1.0) * np.exp(-s / 1.5e-3))
        ring *= 1 - np.exp(-s / 2e-5)  # a rise well under 1 ms
        clean[i0: i0 + s.size] += a * ring / 1.6
    if click_at is not None:  # an unrelated click: a 0.3 ms broadband burst
        i0 = int(click_at * RATE)
        m = int(3e-4 * RATE)
        clean[i0: i0 + m] += 0.4 * rng.standard_normal(m) * np.hanning(m)
    t_ir = np.arange(int(0.4 * RATE)) / RATE
    ir = 0.01 * rng.standard_normal(t_ir.size) * np.exp(-t_ir / 0.06)
    ir[0] = 1.0
    wet = fftconvolve(clean, ir)[:n]
    quiet_peak = np.min([np.max(np.abs(clean[int(tk * RATE): int(tk * RATE) + 200]))
                         for tk in times])
    hum = 0.3 * quiet_peak * (np.sin(2 * np.pi * 50 * ts) + 0.5 * np.sin(2 * np.pi * 150 * ts))
    noise = 0.1 * quiet_peak * rng.standard_normal(n)  # 20 dB below the quietest peak
    return wet + hum + noise


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_synthetic_recording_gives_times_and_points(seed):
    times = bounce_times()
    click = times[3] + 0.4 * (times[4] - times[3])
    x = synthetic_recording(times, seed=seed, click_at=click)
    found = detect_impacts(x, RATE)
    assert found.size == times.size
    np.testing.assert_allclose(found, times, rtol=0, atol=1e-4)
    ref = reduce_bounces([times])
    got = reduce_bounces([found])
    flights = np.diff(times)
    long = (flights[:-1] >= 0.2) & (flights[1:] >= 0.2)
    assert long.sum() >= 4
    np.testing.assert_allclose(got.data.v[long], ref.data.v[long], rtol=0, atol=1e-3)
    np.testing.assert_allclose(got.data.e[long], ref.data.e[long], rtol=0, atol=1e-3)


def test_the_click_is_found_without_the_physics_and_dropped_with_it():
    times = bounce_times()
    click = times[3] + 0.4 * (times[4] - times[3])
    x = synthetic_recording(times, click_at=click)
    raw = detect_impacts(x, RATE, physics=False)
    assert raw.size == times.size + 1 and np.min(np.abs(raw - click)) < 1e-3


@pytest.mark.parametrize("kind", ["u8", "i16", "i24", "i32", "f32", "stereo"])
def test_wav_formats_read_alike(tmp_path, kind):
    rng = np.random.default_rng(3)
    x = 0.5 * np.sin(np.arange(4800) / 7.0) + 0.01 * rng.standard_normal(4800)
    path = tmp_path / f"{kind}.wav"
    if kind == "u8":
        wavfile.write(path, 48000, np.round(x * 127 + 128).astype(np.uint8))
        tol = 1 / 100
    elif kind == "i16":
        wavfile.write(path, 48000, np.round(x * 32767).astype(np.int16))
        tol = 1e-4
    elif kind == "i24":  # written by the standard library: 3 bytes per sample
        v = np.round(x * (2 ** 23 - 1)).astype(np.int32)
        b = np.stack([(v >> s) & 0xFF for s in (0, 8, 16)], axis=1).astype(np.uint8)
        with wave.open(str(path), "wb") as w:
            w.setnchannels(1)
            w.setsampwidth(3)
            w.setframerate(48000)
            w.writeframes(b.tobytes())
        tol = 1e-6
    elif kind == "i32":
        wavfile.write(path, 48000, np.round(x * (2 ** 31 - 1)).astype(np.int32))
        tol = 1e-8
    elif kind == "f32":
        wavfile.write(path, 48000, x.astype(np.float32))
        tol = 1e-7
    else:
        wavfile.write(path, 48000, np.stack([x, x], axis=1).astype(np.float32))
        tol = 1e-7
    y, rate = read_audio(path)
    assert rate == 48000.0
    np.testing.assert_allclose(y, x, atol=tol)


def test_bad_recordings(tmp_path, monkeypatch):
    with pytest.raises(RecordingError, match="no such file"):
        read_audio(tmp_path / "missing.wav")
    junk = tmp_path / "junk.wav"
    junk.write_bytes(b"not audio at all")
    with pytest.raises(RecordingError, match="not a WAV file"):
        read_audio(junk)
    m4a = tmp_path / "drop.m4a"
    m4a.write_bytes(b"\x00\x00\x00\x18ftypM4A ")
    monkeypatch.setattr("shutil.which", lambda name: None)
    with pytest.raises(RecordingError, match="convert it to WAV first"):
        read_audio(m4a)
    empty = tmp_path / "empty.wav"
    wavfile.write(empty, 8000, np.zeros(0, dtype=np.int16))
    with pytest.raises(RecordingError, match="empty"):
        read_audio(empty)
    long = tmp_path / "long.wav"
    wavfile.write(long, 8000, np.zeros(8000 * 3, dtype=np.int16))
    monkeypatch.setattr("viscontact.fit.audio.MAX_SECONDS", 2.0)
    with pytest.raises(RecordingError, match="3 s long; at most 2 s"):
        read_audio(long)
    silent = np.random.default_rng(0).standard_normal(44100) * 1e-3
    assert detect_impacts(silent, RATE).size < 3
