"""Image error metrics, the same as the CLI's (client/cli/image_metrics.h):
    rmse    = sqrt(mean over pixels and channels of (x - r)^2)
    rel_mse = mean over pixels and channels of (x - r)^2 / (r^2 + 1e-2)
"""

from __future__ import annotations

import numpy as np


def _check(image: np.ndarray, reference: np.ndarray):
    if image.shape != reference.shape:
        raise ValueError(f"image is {image.shape} but the reference is {reference.shape}")
    return image.astype(np.float64), reference.astype(np.float64)


def rmse(image: np.ndarray, reference: np.ndarray) -> float:
    x, r = _check(image, reference)
    return float(np.sqrt(np.mean((x - r) ** 2)))


def rel_mse(image: np.ndarray, reference: np.ndarray) -> float:
    x, r = _check(image, reference)
    return float(np.mean((x - r) ** 2 / (r * r + 1e-2)))
