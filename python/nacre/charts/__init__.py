# SPDX-License-Identifier: BSD-3-Clause
"""The charts of nacre's output directories, one module per kind, run by the nacre program at
the end of a run (PYTHONPATH naming the directory that holds the nacre package):

    python3 -m nacre.charts.mc DIR [--quiet]      Monte Carlo run: energy_force.png, crack.png, r_curve.png
    python3 -m nacre.charts.dyn DIR [DUMP.h5] [--magnify M] [--raster] [--quiet]
                                                  dynamic run: energy_force.png, crack.png, r_curve.png
    python3 -m nacre.charts.sweep DIR [--quiet]   sweep: sweep.png
    python3 -m nacre.charts.bench DIR [--quiet]   bench: bench.png

They only draw: the data (r_curve.csv, summary.json's toughening ratio, sweep.csv) are the
program's. Each PNG is written to a temporary sibling and renamed, so a failure leaves no
truncated chart. Without matplotlib a module prints one warning and exits 0.
"""
