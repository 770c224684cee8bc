// Placeholder of the microgeometry simulator (issue 3), being written.
#pragma once
