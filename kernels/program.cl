/* Every kernel carom builds, in one program (the entry kernels/embed.cmake
 * inlines). The include guards of physics.h and particle.h keep each
 * definition single. */
#include "step.cl"
#include "resident.cl"
#include "pairwise.cl"
#include "bench.cl"
