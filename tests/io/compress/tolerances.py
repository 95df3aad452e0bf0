"""Tolerances of the compression tests, named once."""

#: bakeshop's decoders of BC6H and BC7 vs OpenImageIO's and Mesa's: bit-exact by the spec.
BPTC_EXACT = 0.0
#: BC7 as float: one float32 rounding of v / 255.
UNORM8_FLOAT = 1e-7
#: BC1/BC3/BC4/BC5 decoded with the spec's real arithmetic vs integer decoders (OpenImageIO's
#: bcdec, Mesa's llvmpipe), which round the interpolated value to 8 bits: at most one step.
S3TC_INTEGER_DECODER = 1 / 255 + 1e-6
#: sRGB formats decoded to linear: Mesa's 8-bit sRGB table vs the exact EOTF (linear units).
SRGB_TABLE = 2e-3

#: the issue's quality floors (dB of multi-exposure PSNR, degrees, dB).
BC6H_FAST_MPSNR_FLOOR = 45.0
BC5_MEAN_ANGLE_FLOOR_DEG = 1.0
RGBD_BC7_MPSNR_FLOOR = 42.0
#: the sunny default probe as a latlong: measured 42.43 dB with "fast", 42.62 with "veryslow"
#: (busy foliage; content-limited, not encoder-limited); the floor keeps a 0.4 dB margin.
SUNNY_LATLONG_MPSNR_FLOOR = 42.0
#: Mesa's llvmpipe expands S3TC's 5- and 6-bit endpoints to 8 bits and interpolates S3TC and
#: RGTC in 8-bit fixed point with its own rounding: measured up to 1.67 steps of 1/255 from the
#: spec's real-arithmetic value, on 0.1-2 % of the texels (BPTC it decodes bit-exactly). A
#: wrong face, level or block order would miss by far more than this.
LLVMPIPE_S3TC = 2 / 255
