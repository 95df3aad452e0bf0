"""Every numerical tolerance the tests use, named once (as colour-science keeps them)."""

#: float32 round trip through a lossless float codec: bit-exact.
EXACT = 0.0
