// A file of the core that includes World: the floors test must refuse it.
#include "world/world.h"
