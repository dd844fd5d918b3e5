// The one value the course contract and the engine share: as the other party of a collision,
// -1 means a wall (in the course the table's wall, Collision::other; in the engine's event log
// any wall, EventRecord::other, with the wall's index beside it), so that a course's collisions
// and an engine's log compare as they are.
#pragma once

namespace billiard {

inline constexpr int kWall = -1;

}  // namespace billiard
