-- Keep the head level (docs/extending.md, "A head-level fitness"): the mean tilt of the head over the run, degrees —
-- 0 for a head that never tilts; weight it negatively. When the head drops below params.min_height the robot has
-- fallen: stop() ends the parameter set there, and the term adds params.fall_penalty degrees.
--   params.body           the body kept level ("Middle/Head")
--   params.min_height     m; below it the robot has fallen (0.25)
--   params.fall_penalty   degrees added for a fall (90)
local head = orcs.body(params.body or "Middle/Head")
local min_height = params.min_height or 0.25
local fall_penalty = params.fall_penalty or 90
local tilt_sum, steps, fallen

function start()
  tilt_sum, steps, fallen = 0, 0, false
end

function step(dt)
  tilt_sum = tilt_sum + orcs.tilt(head)
  steps = steps + 1
  local _, height = orcs.position(head)
  fallen = height < min_height
end

function stop()
  return fallen
end

function finish()
  local mean = steps > 0 and tilt_sum / steps or 0
  return fallen and mean + fall_penalty or mean
end
