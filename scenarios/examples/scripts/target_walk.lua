-- Walk to a target and stop there (docs/extending.md, "A target-reaching fitness"): minus the distance from the
-- body to the target on the floor at the end of the run, m, less a penalty for still moving then — a walker that
-- overshoots, or passes the target at speed, scores worse than one that arrives and stands. Higher is better.
--   params.body          the body that must arrive ("Middle/UpperBody")
--   params.target        {x, z}: the target on the floor, m, relative to where the body starts (+z forward)
--   params.still_weight  s: metres of distance one m/s of speed at the end costs (1)
local body = orcs.body(params.body or "Middle/UpperBody")
local target = params.target or {0, 0.3}
local still_weight = params.still_weight or 1
local goal_x, goal_z

function start()
  local x, _, z = orcs.position(body)
  goal_x, goal_z = x + target[1], z + target[2]
end

function finish()
  local x, _, z = orcs.position(body)
  local vx, _, vz = orcs.velocity(body)
  local distance = math.sqrt((x - goal_x) ^ 2 + (z - goal_z) ^ 2)
  local speed = math.sqrt(vx ^ 2 + vz ^ 2)
  return -distance - still_weight * speed
end
