// Tap to look: a tap on a bird's-eye view turns another view to look at that spot. The
// daemon's PixelToRay gives the ground point the tapped pixel shows (in the robot frame);
// the yaw and pitch that point the view from its own origin there follow (REP-103 angles:
// yaw left-positive about z, pitch positive looking down).
export async function lookAt(link, fromView, pixel, targetView) {
  const ray = await link.call('PixelToRay', { view: fromView, u: pixel.u, v: pixel.v });
  if (!ray.valid) throw new Error('no ground there');
  const target = await link.call('GetView', { name: targetView });
  const o = (target.pose && target.pose.translation) || {};
  const p = ray.surfacePoint || {};
  const dx = (p.x || 0) - (o.x || 0);
  const dy = (p.y || 0) - (o.y || 0);
  const dz = (p.z || 0) - (o.z || 0);
  const deg = 180 / Math.PI;
  return { yawDeg: Math.atan2(dy, dx) * deg, pitchDeg: Math.atan2(-dz, Math.hypot(dx, dy)) * deg };
}
