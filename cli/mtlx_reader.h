// Placeholder of mtlx_reader (issue 7), being written.
#pragma once
