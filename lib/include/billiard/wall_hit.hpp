// The one value the course contract and the engine share: as the other party of an event, -1
// means no other disc (in the course the table's wall, Collision::other; in the engine's event
// log, EventRecord::other, any wall, with the wall's index beside it, or no party at all for a
// disc falling asleep or waking up), so that a course's collisions and an engine's log compare as
// they are. The engine uses no other negative value; values below -1 are the course's walls stage
// alone (walls[k] is -2 - k).
#pragma once

namespace billiard {

inline constexpr int kWall = -1;

}  // namespace billiard
