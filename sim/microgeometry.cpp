#include "microgeometry.h"
