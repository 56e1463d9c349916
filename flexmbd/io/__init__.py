"""Files: SPACAR input files (``.dat``: reading, writing, parameters of studies) and the
checks of the output files a command writes."""
