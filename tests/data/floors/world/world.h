// World, two floors above the core.
#pragma once
