// A file of carom::io that reaches into World: the floors test must refuse it.
#include "world/world.h"
