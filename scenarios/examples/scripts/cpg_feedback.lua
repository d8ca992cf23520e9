-- A central pattern generator with foot-contact feedback, as a script controller (docs/extending.md, "A CPG
-- controller"). One phase oscillator drives the legs: the hips and ankles rock the weight from foot to foot
-- (HipPitch, AnklePitch: the frontal plane), the hips swing the legs forward and back in opposite directions
-- (HipYaw) with a phase lead, and the knee of the leg that carries no weight bends. (Swinging the ankles with the
-- hips tips the robot backwards at every amplitude tried; the feet stay flat instead.) When a foot lands, the phase is pulled
-- towards the phase at which that foot should land (phase resetting): the rhythm entrains to the body's own sway.
--
-- genome[1] frequency, Hz          genome[2] rock amplitude, deg     genome[3] swing amplitude, deg
-- genome[4] knee bend, deg         genome[5] feedback strength, 0…1  genome[6] swing phase lead, rad
local two_pi = 2 * math.pi
local right_foot, left_foot = orcs.body("Right/Foot"), orcs.body("Left/Foot")
local phase, last_time, right_down, left_down

function reset()
  phase, last_time = 0, 0
  right_down, left_down = true, true
end

-- Moves the phase a fraction `strength` of the way towards `target` (radians), the short way round.
local function pull(target, strength)
  phase = phase - strength * math.sin(phase - target)
end

function control(t)
  local frequency, rock, swing, knee, strength, lead = genome[1], genome[2], genome[3], genome[4], genome[5], genome[6]
  phase = (phase + two_pi * frequency * (t - last_time)) % two_pi
  last_time = t
  local right_now, left_now = orcs.contact(right_foot), orcs.contact(left_foot)
  if right_now and not right_down then pull(0, strength) end        -- right foot lands: weight goes right
  if left_now and not left_down then pull(math.pi, strength) end    -- left foot lands: weight goes left
  right_down, left_down = right_now, left_now

  local sway, step = math.sin(phase), math.sin(phase + lead)
  for side, scissor in pairs({Right = 1, Left = -1}) do  -- the legs swing in opposite directions
    orcs.set_angle(side .. "/HipPitch", rock * sway)
    orcs.set_angle(side .. "/AnklePitch", -rock * sway)
    orcs.set_angle(side .. "/HipYaw", scissor * swing * step)
  end
  -- the leg that carries no weight bends its knee
  orcs.set_angle("Right/Knee", knee * math.max(0, -sway))
  orcs.set_angle("Left/Knee", knee * math.max(0, sway))
end
