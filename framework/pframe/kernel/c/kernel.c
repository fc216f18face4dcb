/* The kernel as one compilation unit: each file holds one idea (see kernel.h). */

#include "kernel.h"

#include "laws.c"
#include "banded.c"
#include "assembly.c"
#include "integrator.c"
#include "newton.c"
#include "energy.c"
#include "record.c"
#include "events.c"
#include "implicit.c"
#include "explicit.c"
#include "loop.c"
