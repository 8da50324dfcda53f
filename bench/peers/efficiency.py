"""Statistics of K seeded renders (numpy only): image means and their z-scores, relative variance per
sample, the marginal seconds per sample and equal-time efficiency."""
import math
from statistics import NormalDist

import numpy as np

# relMSE's guard for dark pixels, as in acdf bench-error: (I - R)^2 / (R^2 + 0.01)
DARK_GUARD = 0.01


def mean_and_standard_error(images):
    """The mean of K images over pixels and channels, and its standard error from the seeds' spread."""
    means = images.reshape(len(images), -1).mean(axis=1)
    return float(means.mean()), float(means.std(ddof=1) / math.sqrt(len(means)))


def mean_z(images, reference_images, allowance=0.0):
    """z-score of the difference of two renderers' image means (independent seeds on both sides); a
    relative `allowance` of the reference mean is added to the standard error in quadrature."""
    mean, error = mean_and_standard_error(images)
    reference_mean, reference_error = mean_and_standard_error(reference_images)
    return (mean - reference_mean) / math.hypot(error, reference_error, allowance * reference_mean)


def block_z_scores(images, reference_images, blocks=(4, 4), allowance=0.0):
    """mean_z of each of rows x columns blocks, per channel."""
    def block_means(stack):  # [K, rows, columns, 3]
        rows = np.array_split(np.arange(stack.shape[1]), blocks[0])
        columns = np.array_split(np.arange(stack.shape[2]), blocks[1])
        return np.stack([np.stack([stack[:, r][:, :, c].mean(axis=(1, 2)) for c in columns], axis=1)
                         for r in rows], axis=1)

    a, b = block_means(images), block_means(reference_images)
    reference_mean = b.mean(axis=0)
    standard_error = np.sqrt(a.var(axis=0, ddof=1) / len(a) + b.var(axis=0, ddof=1) / len(b)
                             + (allowance * reference_mean) ** 2)
    return (a.mean(axis=0) - reference_mean) / standard_error


def sidak_z_bound(count, alpha):
    """The |z| a family of `count` two-sided tests at overall level alpha may reach (Sidak)."""
    per_test = 1 - (1 - alpha) ** (1 / count)
    return NormalDist().inv_cdf(1 - per_test / 2)


def relative_variance_per_sample(images, spp, reference):
    """Mean over pixels and channels of the variance across seeds x spp, over reference^2 + 0.01."""
    return float((images.var(axis=0, ddof=1) * spp / (reference ** 2 + DARK_GUARD)).mean())


def seconds_per_sample(seconds, spp_counts):
    """Marginal wall-clock seconds of one sample per pixel: the two counts' median difference (start-up excluded)."""
    low, high = (float(np.median(s)) for s in seconds)
    return (high - low) / (spp_counts[1] - spp_counts[0])


def efficiency(relative_variance, seconds):
    """1 / (relative variance per sample x seconds per sample): higher is better at equal time."""
    return 1.0 / (relative_variance * seconds) if relative_variance > 0 and seconds > 0 else math.nan
