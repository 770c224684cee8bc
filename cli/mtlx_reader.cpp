#include "mtlx_reader.h"
