"""Records -> frozen results: statistics of a study's records, no formatting and no plots.

Imports only the numerical core, numpy, pandas, scipy and statsmodels (numba in rank_kernel.py).
"""
