"""The preview tests' tolerances, named once."""

#: Offscreen render vs the numpy reference after bakeshop's display rule, in 8-bit code values:
#: the issue's bound (1/255) at pixels that are not on an edge.
PREVIEW_CODE_ATOL = 1
#: An edge, for that comparison: a pixel whose reference value moves by more than this many code
#: values when the ray moves a quarter pixel (a ball's silhouette, the sun's rim seen in a mirror
#: ball). There the driver's float32 ray-sphere hit (its hit point is rounded to ~1e-4 of the
#: radius near the rim, where t = -b - sqrt(b^2 - c) cancels) picks a visibly different texel.
PREVIEW_EDGE_CODES = 1
#: Linear radiance of the render vs the reference away from edges (relative): float32 shading,
#: float32 texels and the driver's fixed-point filter weights against float64 (measured 3e-4).
PREVIEW_LINEAR_RTOL = 1e-3
#: A uniform environment of 1 and a DIM of 1: a Lambertian ball shows its albedo to float32.
PREVIEW_UNIFORM_ATOL = 1e-6
#: The shaders' own display step vs bakeshop.image.to_picture, in 8-bit code values.
PREVIEW_DISPLAY_CODES = 1
#: The browser's screenshot (WebGL2 on SwiftShader, 8-bit canvas) vs ``bakeshop preview`` of the
#: same view (moderngl on llvmpipe, bakeshop.image.to_picture), in 8-bit code values: the issue's
#: bounds, mean over the picture and largest away from balls' silhouettes.
BROWSER_MEAN_CODES = 1.0
BROWSER_MAX_CODES = 8
