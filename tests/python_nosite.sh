#!/bin/sh
# Debian's python3 without its site packages (numpy, matplotlib, h5py...): test cli_plot_missing_modules.
exec /usr/bin/python3 -S "$@"
