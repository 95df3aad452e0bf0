"""What is computed from an environment: spherical harmonics, diffuse irradiance and the sun,
specular prefiltering, fresnel baking, exposure and tone mapping.

Import from the submodules, each named for what it holds.
"""
