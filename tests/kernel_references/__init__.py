"""The compiled kernels' plain numpy references: what each `*_kernel.py` of tvl_cli computes,
every element at once, for the tests (and the speed benchmarks) to hold the kernels to."""
