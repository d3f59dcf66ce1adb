/* hsbd: Brownian dynamics of hard bodies with exact hard cores. Umbrella header. */
#ifndef HSBD_H
#define HSBD_H

#include "hsbd/config.h"
#include "hsbd/error.h"
#include "hsbd/field.h"
#include "hsbd/frame.h"
#include "hsbd/io.h"
#include "hsbd/isotonic.h"
#include "hsbd/observe.h"
#include "hsbd/pair.h"
#include "hsbd/rng.h"
#include "hsbd/rods.h"
#include "hsbd/run.h"
#include "hsbd/sim.h"
#include "hsbd/spheres.h"
#include "hsbd/table.h"
#include "hsbd/theory.h"
#include "hsbd/version.h"

#endif
