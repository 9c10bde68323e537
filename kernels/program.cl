/* Every kernel of carom's OpenCL backends, in one program (the entry
 * kernels/embed.cmake inlines). The include guards of physics.h,
 * particle.h and grid.cl keep each definition single. The benchmark's kernels are a
 * program of their own (bench.cl). */
#include "domain_share.cl"
#include "host_grid.cl"
#include "pairwise.cl"
#include "resident.cl"
#include "small_system.cl"
#include "view.cl"
