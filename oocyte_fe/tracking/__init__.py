"""Spindle tracking in polarized-light video: the Multi-Feature Adaptive Kernel Correlation
Filter (MFAKCF) of seed 000, Section II.A and Algorithm 1, built on the KCF of Henriques et
al. 2015 (TPAMI 37:583).

One module per idea: :mod:`.features` (cell-wise HOG and the grayscale-histogram channel),
:mod:`.kcf` (Gaussian kernel correlation, ridge regression in the Fourier domain),
:mod:`.fusion` (APCE reliability and adaptive weights), :mod:`.update` (adaptive learning
rate, loss and re-detection), :mod:`.tracker` (Algorithm 1), :mod:`.metrics` (OTB precision
and success), :mod:`.video` (frames in and out), :mod:`.synthetic` (the benchmark's
polarized-light sequence generator) and :mod:`.benchmark`. Positions are in pixels inside;
:class:`.video.Calibration` converts to um. See docs/tracking.md.
"""
