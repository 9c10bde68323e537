# Issue 11, items 14-16 and 18 (subnormals): the ranges in which float32
# results are valid (README, "Limits"). Values outside them are refused with
# the value and the range named; a step lost in the float spacing of the
# positions is refused, one close to it warned about; coincident disks are
# refused with the pair, overlapping ones reported.
carom_cli_test(range_dt_huge fail "dt 1e\\+30 is outside \\[1e-18, 1e\\+18\\]" "${run}|--dt|1e30")
carom_cli_test(range_speed_huge fail "speed 1e\\+30 is outside \\[0, 1e\\+18\\]" "${run}|--speed|1e30")
carom_cli_test(range_gravity_huge fail "gravity \\(1e\\+38, 0\\) is stronger than 1e\\+18" "${run}|--gravity|1e38|0")
carom_cli_test(range_mass_huge fail "mass 2e\\+38 is outside \\[1e-15, 1e\\+15\\]" "${run}|--mass|2e38")
carom_cli_test(range_scale_1e19 fail "box width 1e\\+19 is outside \\[1e-18, 1e\\+18\\]"
               "${run}|--box|1e19|1e19|--radius|1e17|--speed|1e19|--particles|10")
carom_cli_test(range_scale_1e17 fail "times the box diagonal 1.41421e\\+17 is 1.41421e\\+34; results are valid up to 1e\\+18"
               "${run}|--box|1e17|1e17|--radius|1e15|--speed|1e17|--particles|10")
carom_cli_test(range_dt_across_box fail "a step of dt 200 moves the fastest disk \\(speed up to 1\\) by 200, more than the box side 102.333; the largest dt is 102.333"
               "${run}|--dt|200")
carom_cli_test(range_packing_subnormal fail "packing 1.4013e-45 makes a 1.4973e\\+24 x 1.4973e\\+24 box; boxes up to 1e\\+18 are valid"
               "${run}|--packing|1e-45")
carom_cli_test(range_box_loses_motion fail "less than the float32 spacing 0.015625 .*the largest box is 131072"
               "${run}|--box|150000|150000")
carom_cli_test(range_far_disks fail "far_disks.csv: a step moves a typical disk \\(speed 1, step 0.01\\) by 0.01, less than the float32 spacing 0.015625"
               "${run}|--input-state|${data}/far_disks.csv|--box|160000|100")
carom_cli_test(range_box_warns pass "warning: a step moves a typical disk by 0.01, only 5.12 float32 spacings.*boxes up to 16384 keep it within 5 %"
               "run|--backend|cpu|--steps|2|--box|20000|20000")
carom_cli_test(range_gravity_at_rest pass "carom run: 1000 disks"
               "run|--backend|cpu|--steps|2|--speed|0|--gravity|0|-1")
carom_cli_test(range_subnormal_radius fail "subnormal_radius.csv: particle 0: radius 9.99995e-41 is outside \\[1e-18, 1e\\+18\\]"
               "${run}|--input-state|${data}/subnormal_radius.csv|--box|10|10")
# A NaN centre is no place, not one "outside the box".
carom_cli_test(range_nan_position fail "nan_position.csv: particle 0: position must be finite, got \\(nan, 5\\)"
               "${run}|--input-state|${data}/nan_position.csv|--box|10|10")
carom_cli_test(range_radius_below_float fail "radius_below_float.csv:2: column 'radius': '1e-50' is too small for a 32-bit float"
               "${run}|--input-state|${data}/radius_below_float.csv|--box|10|10")
carom_cli_test(range_subnormal_mass fail "subnormal_mass.csv: particle 0: mass 9.99995e-41 is outside \\[1e-15, 1e\\+15\\]"
               "${run}|--input-state|${data}/subnormal_mass.csv|--box|10|10")
carom_cli_test(range_coincident_disks fail "coincident_disks.csv: particles 0 and 1 have the same centre \\(5, 5\\)"
               "${run}|--input-state|${data}/coincident_disks.csv|--box|10|10")
carom_cli_test(range_overlapping_disks pass "warning: 1 pair\\(s\\) of disks overlap, the deepest particles 0 and 1 by 0.5 \\(25 % of their contact distance\\)"
               "run|--backend|cpu|--steps|2|--input-state|${data}/overlapping_disks.csv|--box|20|20")
# At the edges of the ranges every JSON number is a number (a mass of 2e38 printed a null pressure).
set(number "-?[0-9][0-9.e+-]*")
carom_cli_test(range_edges_json pass
               "\"total\": {\n *\"final\": ${number},\n *\"initial\": ${number}.*\"wall_pressure\": {\n *\"Z\": ${number},\n *\"bottom\": ${number},\n *\"left\": ${number},\n *\"mean\": ${number},\n *\"right\": ${number},\n *\"top\": ${number}"
               "run|--backend|cpu|--steps|50|--particles|300|--mass-min|1e-15|--mass-max|1e15|--packing|0.1|--json")
