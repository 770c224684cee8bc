#include "alta_reader.h"
