# Numbers on the command line and the inputs carom reads: every numeric
# option of every subcommand is parsed strictly (no wrap-around, no empty
# string as 0), and inputs are bounded before memory is spent on them
# (included by tests/CMakeLists.txt, whose carom_cli_test and out it uses).

set(base "run|--backend|cpu|--particles|10|--output-state|${out}")
set(u64 "allowed: whole numbers from 0 to 18446744073709551615")
# A value that wraps would run (almost) forever: these must fail at once.
# (Empty values are tested in outputs_test.py: this script cannot pass one.)
function(carom_input_test name regex args)
    carom_cli_test(${name} fail "${regex}" "${args}")
    set_tests_properties(cli.${name} PROPERTIES TIMEOUT 60)
endfunction()

carom_input_test(steps_negative "--steps: '-1' is out of range; ${u64}" "${base}|--steps|-1")
carom_input_test(steps_past_2_64 "--steps: '18446744073709551616' is out of range; ${u64}"
                 "${base}|--steps|18446744073709551616")
carom_input_test(steps_octal_or_hex "--steps: '0x10' is not a whole number" "${base}|--steps|0x10")
carom_input_test(seed_negative "--seed: '-1' is out of range; ${u64}" "${base}|--steps|1|--seed|-1")
carom_input_test(seed_2_64 "--seed: '18446744073709551616' is out of range" "${base}|--steps|1|--seed|18446744073709551616")
carom_input_test(seed_huge "--seed: '99999999999999999999999' is out of range" "${base}|--steps|1|--seed|99999999999999999999999")
carom_input_test(speed_trailing_text "--speed: '1.5x' is not a number" "${base}|--steps|1|--speed|1.5x")
carom_input_test(every_negative
                 "--every: '-1' is out of range; allowed: whole numbers from 1 to 18446744073709551615"
                 "${base}|--steps|1|--every|-1")
carom_input_test(particles_past_32_bits
                 "--particles: '5000000000' is out of range; allowed: whole numbers from 1 to 1000000000"
                 "${base}|--steps|1|--particles|5000000000")
carom_input_test(bench_seed_negative "--seed: '-1' is out of range; ${u64}" "bench|--quick|--methods|cpu|--seed|-1")
carom_input_test(validate_seed_negative "--seed: '-1' is out of range; ${u64}" "validate|--quick|--seed|-1")
if(CAROM_HAVE_VIEWER)
    carom_input_test(view_frames_negative
                     "--frames: '-1' is out of range; allowed: whole numbers from 1 to 18446744073709551615"
                     "view|--backend|cpu|--frames|-1")
endif()

# --dt auto splits steps by --max-travel: 0 (off) contradicts it.
carom_input_test(dt_auto_max_travel_zero
                 "--dt auto splits each step so that no disk moves more than --max-travel radii; --max-travel 0"
                 "${base}|--steps|1|--dt|auto|--max-travel|0")
# --skin sizes the CPU engine's pairwise neighbour lists: refused out of range and where no lists take it; given
# alone, it asks --backend auto for the CPU.
carom_input_test(skin_negative "skin must be a finite number >= 0 \\(0 = automatic\\), got -1" "${base}|--steps|1|--skin|-1")
carom_input_test(skin_too_wide "skin 9 is more than 8 times the largest radius 1 .*allowed: up to 8, or 0 \\(automatic\\)"
                 "${base}|--steps|1|--skin|9")
carom_input_test(skin_simultaneous "WorldDef::skin \\(--skin\\) sizes the CPU engine's neighbour lists.*got 0.5"
                 "${base}|--steps|1|--skin|0.5|--collisions|simultaneous")
carom_cli_test(skin_picks_the_cpu pass "\"backend_reason\": \"--backend auto: --skin sizes the CPU engine's neighbour lists\""
               "run|--particles|100|--steps|5|--skin|0.5|--json")
# The CPU backend has no devices or pipelines: naming one is a mistake.
carom_input_test(cpu_with_device "--device: '5' needs --backend opencl; the cpu backend has no devices to choose from" "${base}|--steps|1|--device|5")
carom_input_test(cpu_with_pipeline "--pipeline: 'host-grid' needs --backend opencl; the cpu backend has one pipeline"
                 "${base}|--steps|1|--pipeline|host-grid")

# Counts checked against carom's limit before anything is allocated.
carom_input_test(bench_size_past_limit
                 "--sizes: '1000000001' is out of range; allowed: whole numbers from 1 to 1000000000"
                 "bench|--methods|cpu|--sizes|1000000001")
carom_input_test(bench_size_4e9 "--sizes: '4e9' is out of range; allowed: whole numbers from 1 to 1000000000"
                 "bench|--methods|cpu|--sizes|4e9")
carom_input_test(validate_particles_cap
                 "--particles: '100000000' is out of range; allowed: whole numbers from 256 to 1000000"
                 "validate|--quick|--particles|100000000")
# A file without a newline (here endless zero bytes) is refused at the line cap.
carom_input_test(input_state_endless_line
                 "/dev/zero:1: line longer than 4096 bytes; in a state file lines are at most 4096 bytes"
                 "run|--backend|cpu|--steps|1|--output-state|${out}|--input-state|/dev/zero|--box|10|10")

# Empty values, memory figures, FIFOs and a forged checkpoint need a script
# to set up: outputs_test.py, registered in io_tests.cmake.

# Real numbers are decimal, as a person types them: strtod's hexadecimal and
# leading '+' or space are refused, in every option and in bench --sizes,
# whose empty entries are refused too instead of skipped.
carom_input_test(speed_hex "--speed: '0x10' is not a number; allowed: a decimal number" "${base}|--steps|1|--speed|0x10")
carom_input_test(dt_plus "--dt: '\\+0.5' is not a number; allowed: a decimal number" "${base}|--steps|1|--dt|+0.5")
carom_input_test(dt_space "--dt: ' 0.5' is not a number; allowed: a decimal number" "${base}|--steps|1|--dt| 0.5")
carom_input_test(gravity_hex "--gravity: '0x1p3' is not a number" "${base}|--steps|1|--gravity|0|0x1p3")
carom_input_test(bench_budget_hex "--budget-ms: '0x10' is not a number" "bench|--quick|--methods|cpu|--budget-ms|0x10")
carom_input_test(validate_dt_plus "--dt: '\\+0.01' is not a number" "validate|--quick|--dt|+0.01")
carom_input_test(bench_sizes_hex "--sizes: '0x10' is not a number of particles"
                 "bench|--quick|--methods|cpu|--sizes|0x10")
carom_input_test(bench_sizes_empty_entry "--sizes: '1000,,2000' has an empty entry"
                 "bench|--quick|--methods|cpu|--sizes|1000,,2000")
carom_input_test(bench_methods_empty_entry "--methods: 'cpu,' has an empty entry" "bench|--quick|--methods|cpu,")
# A value a 32-bit float turns into 0 or infinity would change its meaning
# (a disk at rest, gravity or substeps off): refused, naming the value typed.
carom_input_test(speed_underflow "--speed: '1e-50' is too small for a 32-bit float and would read as 0"
                 "${base}|--steps|1|--speed|1e-50")
carom_input_test(gravity_underflow "--gravity: '-1e-50' is too small for a 32-bit float"
                 "${base}|--steps|1|--gravity|0|-1e-50")
carom_input_test(max_travel_underflow "--max-travel: '1e-50' is too small for a 32-bit float"
                 "${base}|--steps|1|--max-travel|1e-50")
carom_input_test(dt_underflow "--dt: '1e-50' is too small for a 32-bit float" "${base}|--steps|1|--dt|1e-50")
carom_input_test(speed_overflow "--speed: '1e50' is too large for a 32-bit float" "${base}|--steps|1|--speed|1e50")
# A refusal shows the value as typed, not as std::to_string prints a float.
carom_input_test(box_zero "--box must be two finite numbers > 0, got 0 10" "${base}|--steps|1|--box|0|10")
