"""Tolerances of the photo tests, named once (the issue's bounds where it states them)."""

#: recovered response vs the true curve over the well-exposed codes (10-95 % of full scale),
#: after the one free scale per channel: the issue's bound.
RESPONSE_CURVE = 0.02
#: merged radiance vs truth where some frame saw it (RMS of the relative error): the issue's.
MERGE_RMS = 0.01
#: a clipped sun's irradiance recovered from its aureole (relative): the issue's bound.
SUN_IRRADIANCE = 0.10
#: OpenCV's calibrate + merge keeps less than this share of a clipped sun (the issue's claim).
OPENCV_SUN_LOSS = 0.5
#: bakeshop's multi-exposure PSNR over OpenCV's on the same stack (dB): the issue's bound.
MPSNR_GAIN_DB = 1.0
#: alignment of known sub-pixel shifts (pixels): the issue's bound.
ALIGN_PX = 0.1
#: the ball's circle found in a rendered photo (pixels).
BALL_PX = 0.1
#: unwrapped ball vs the probe it reflects, away from the rim (RMS relative): the issue's bound.
UNWRAP_RMS = 0.01
#: the two-view merge vs the probe where one view saw the photographer (RMS relative).
TWO_VIEW_RMS = 0.02
