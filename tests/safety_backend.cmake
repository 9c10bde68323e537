# The backends' limits from the command line: a run whose largest disk makes
# the grid's cells far too wide for the rest warns with the cost, naming the
# largest and the typical radius.
carom_cli_test(large_radius_warns pass
               "warning: the largest disk \\(radius 20\\) sizes the grid's cells for all 1501 disks, whose typical \\(median\\) radius is 0.5: each step costs about [0-9]+ times"
               "run|--scene|${data}/large_radius.toml")
