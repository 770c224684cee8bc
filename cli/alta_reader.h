// Placeholder of alta_reader (issue 7), being written.
#pragma once
