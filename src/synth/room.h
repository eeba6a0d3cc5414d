/* room.h: a busy background that stays consistent across views (`wiresketch
 * scene NAME --background room`): the object stands in a box room, its
 * walls, floor and ceiling painted with hard-edged patterns, so that a
 * capture's clutter (edges at every orientation and at depths other than
 * the object's) is in every view as the same 3D room.
 *
 * The room is the axis-aligned box around the object's centre c with walls
 * at c.x +- WS_ROOM_HALF and c.y +- WS_ROOM_HALF, the floor at height
 * floor_z and the ceiling WS_ROOM_HALF above c: far around the object
 * (whose size is about 1.5, the cameras 4 from c), as a room is around an
 * object on a stand, when the floor is WS_ROOM_FLOOR below c (`--background
 * room`); or with the object standing on the floor, as on a table, when
 * floor_z is the object's lowest point (`--background floor`). Patterns: the floor in tiles of 1 with dark grout and a
 * rug; each wall in two-tone stripes of its own period and colour, with a
 * skirting band and dark-framed pictures; the ceiling in panels. */
#ifndef WS_SYNTH_ROOM_H
#define WS_SYNTH_ROOM_H
#include "render/camera.h"
#include "io/image.h"
#include "nn/base/status.h"

#define WS_ROOM_HALF 8.0
#define WS_ROOM_FLOOR 3.0

/* The colour of the room seen along the world ray from `origin` in
 * direction `dir` (any length) of the room around `center` with its floor
 * at height floor_z; an origin outside the room sees a neutral grey. */
void ws_room_colour(const double center[3], double floor_z, const double origin[3], const double dir[3],
                    float rgb[3]);

/* The room around `center` seen by cam: img (allocated here: 3 x height x
 * width), each pixel the average of supersample^2 rays spread evenly over
 * it as the object renderers cast them (camera.h: ws_camera_pixel_ray). */
int ws_room_render(const ws_camera *cam, const double center[3], double floor_z, int supersample, ws_image *img,
                   ws_status *st);

#endif
