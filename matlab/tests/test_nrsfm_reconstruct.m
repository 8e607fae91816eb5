% test_nrsfm_reconstruct: nrsfm_reconstruct (the MEX file) from Octave on a
% noise-free sequence made here (K = 2 basis shapes, a camera turning 120
% degrees): the generating shapes are recovered, W is reproduced from the
% returned arrays, options reach the reconstruction, equal observation
% weights change nothing, a mask hides entries, and bad input is an error
% with the tool's message. Run by ctest (matlab/CMakeLists.txt).
F = 60; P = 20; K = 2;
% Basis shapes: points on a twisted helix (S1) and a bending mode (S2).
p = 0:P-1;
S1 = [cos(0.7 * p); sin(0.7 * p); 0.15 * p - 1.4];
S2 = [0.3 * p / P; -0.2 * cos(p); 0.1 * sin(2 * p)];
W = zeros(2 * F, P);
truth = zeros(3 * F, P);               % camera frame, rows x_t, y_t, z_t
for t = 1:F
  a = (t - 1) / (F - 1) * 2 * pi / 3 - pi / 3;   % -60 .. 60 degrees about y
  b = 0.3 * sin(2 * pi * t / F);                  % a nod about x
  Ry = [cos(a) 0 sin(a); 0 1 0; -sin(a) 0 cos(a)];
  Rx = [1 0 0; 0 cos(b) -sin(b); 0 sin(b) cos(b)];
  S_t = S1 + 0.8 * sin(4 * pi * t / F) * S2;
  X = Rx * Ry * S_t;
  truth(3 * t - 2 : 3 * t, :) = X;
  W(2 * t - 1 : 2 * t, :) = X(1:2, :) + [0.5; -0.25];
end

[model, info] = nrsfm_reconstruct(W, K);
assert(isequal(size(model.rotations), [3 3 F]), 'rotations 3 x 3 x F');
assert(isequal(size(model.weights), [F K]), 'weights F x K');
assert(isequal(size(model.basis), [3 P K]), 'basis 3 x P x K');
assert(isequal(size(model.points_object), [3 P F]), 'points_object 3 x P x F');
assert(isequal(size(model.translations), [2 F]), 'translations 2 x F');
assert(info.num_frames == F && info.num_points == P && info.num_bases == K, 'info sizes');
assert(info.solution_usable, 'usable');
assert(info.reprojection_rms < 1e-6, sprintf('reprojection RMS %g', info.reprojection_rms));
% W from the arrays: points_camera(1:2, :, t) + translations(:, t).
largest = 0;
for t = 1:F
  R = model.rotations(:, :, t);
  assert(norm(R * R' - eye(3)) < 1e-12 && abs(det(R) - 1) < 1e-12, 'a rotation');
  S_t = zeros(3, P);
  for k = 1:K
    S_t = S_t + model.weights(t, k) * model.basis(:, :, k);
  end
  assert(max(max(abs(S_t - model.points_object(:, :, t)))) < 1e-12, 'S_t = sum_k l_tk S_k');
  assert(max(max(abs(R * S_t - model.points_camera(:, :, t)))) < 1e-12, 'X_t = R_t S_t');
  W_t = model.points_camera(1:2, :, t) + repmat(model.translations(:, t), 1, P);
  largest = max(largest, max(max(abs(W_t - W(2 * t - 1 : 2 * t, :)))));
end
assert(largest < 1e-6, sprintf('W reproduced to %g', largest));
% The shapes: camera-frame e3D against the generating truth.
camera = reshape(permute(model.points_camera, [1 3 2]), [], P);
e = nrsfm_e3d(truth, camera);
fprintf('noise-free K = 2: camera-frame e3D %.2e, reprojection RMS %.2e\n', e, ...
        info.reprojection_rms);
assert(e < 1e-3, sprintf('e3D %g', e));

% Options by name (any case); info.options records them as the tool does.
[m2, i2] = nrsfm_reconstruct(W, K, 'INIT', 'rigid', 'priors', 'manual', 'Max_Iterations', 7, ...
                             'temporal_shape', 0.5);
assert(strcmp(i2.start_used, 'rigid'), 'init reaches the start');
assert(strcmp(i2.options.max_iterations, '7'), 'max_iterations in info.options');
assert(i2.stages(2).iterations <= 7, 'max_iterations reaches the solver');
assert(i2.term_weights.temporal_shape == 0.5, 'a term weight');

% Equal observation weights: the unweighted reconstruction.
[m3, i3] = nrsfm_reconstruct(W, K, 'observation_weights', 0.3 * ones(F, P));
assert(max(abs(m3.points_camera(:) - model.points_camera(:))) < 1e-9, 'equal weights');
assert(strcmp(i3.options.confidence_weights, 'true'), 'weights recorded');

% A mask (logical, F x P) hides entries; point 5 seen in frame 1 only is
% left out with a warning and is NaN.
mask = true(F, P);
mask(2:end, 5) = false;
mask(10, 1:3) = false;
lastwarn('');
[m4, i4] = nrsfm_reconstruct(W, K, 'mask', mask);
[message, id] = lastwarn();
assert(strcmp(id, 'nrsfm:warning'), 'warning identifier');
assert(~isempty(strfind(message, 'left out of the reconstruction')), message);
assert(isequal(m4.dropped_points, 5), 'dropped_points is 1-based');
assert(all(isnan(m4.basis(:, 5, 1))), 'the left-out point is NaN');
assert(i4.num_visible == F * P - (F - 1) - 3, 'num_visible');

% Uncertainty ('uncertainty', true): the same sequence with noise of known
% std, the data term alone (priors manual: the covariance is that of its
% estimate, which no prior biases). The arrays' frame order is the summary's
% (its worst frame), and the true points lie inside their 95 % ellipsoids
% at about the nominal rate after the e3D alignment, whose rotation turns
% each covariance (docs/uncertainty.md).
randn('state', 3);
sigma = 0.01;
Wn = W + sigma * randn(size(W));
[mu, iu] = nrsfm_reconstruct(Wn, K, 'uncertainty', true, 'noise_std', sigma, ...
                             'priors', 'manual');
assert(isempty(model.points_covariance) && isempty(model.rotations_covariance), ...
       'no covariance without uncertainty');
assert(isequal(size(mu.points_covariance), [3 3 P F]), 'points_covariance 3 x 3 x P x F');
assert(isequal(size(mu.rotations_covariance), [3 3 F]), 'rotations_covariance 3 x 3 x F');
frame_std = zeros(F, 1);
for t = 1:F
  for q = 1:P
    C = mu.points_covariance(:, :, q, t);
    assert(norm(C - C') <= 1e-12 * norm(C) && min(eig(C)) > -1e-12 * norm(C), 'a covariance');
    frame_std(t) = frame_std(t) + trace(C) / P;
  end
end
[~, worst] = max(frame_std);
assert(worst - 1 == iu.diagnostics.uncertainty_worst_frame, 'frame order (0-based in info)');
X = truth - repmat(mean(truth, 2), 1, P);
camera = reshape(permute(mu.points_camera, [1 3 2]), [], P);
Xhat = camera - repmat(mean(camera, 2), 1, P);
[~, Y] = nrsfm_e3d(truth, camera);
inside = 0;
for t = 1:F
  for q = 1:P
    d = X(3 * t - 2 : 3 * t, q) - Y * Xhat(3 * t - 2 : 3 * t, q);
    inside = inside + (d' * ((Y * mu.points_covariance(:, :, q, t) * Y') \ d) <= 7.8147);
  end
end
fprintf('noisy K = 2, sigma %g: %.3f of the true points inside their 95 %% ellipsoids\n', ...
        sigma, inside / (F * P));
% Measured 0.970 here; noise states 1-6 at sigma 0.003 / 0.01 / 0.03 gave
% 0.882-0.971 (the points of a frame share their rotation's error, so one
% sequence's fraction spreads far more than independent points' would).
assert(inside / (F * P) >= 0.85 && inside / (F * P) <= 0.99, 'calibration');

% Errors: identifier nrsfm:error, the tool's message.
cases = {
  {{W, K, 'bogus', 1}, 'unknown option ''bogus''; the options are mask, cameras, observation_weights'}
  {{W, 0}, '--K: must be an integer >= 1 or ''auto'', got ''0'''}
  {{W(1:end-1, :), K}, 'W: 119 rows is not a multiple of 2 (expected rows u, v per frame)'}
  {{W, K, 'init', 'nope'}, '--init: start: unknown value "nope" (expected one of auto, factorization, rigid, triple)'}
  {{W, K, 'max_iterations', 'many'}, 'max_iterations must be an integer, got ''many'''}
  {{W, K, 'observation_weights', ones(3, 3)}, 'observation_weights is 3 x 3, expected 60 x 20'}
  {{W, K, 'observation_weights', -ones(F, P)}, 'weights must be finite and >= 0'}
  {{W, K, 'mask'}, 'usage: [model, info] = nrsfm_reconstruct(W, K, ''Name'', value, ...)'}
  {{'W', K}, 'W must be a real full 2-D numeric matrix, got a char array'}
  {{W, K, 'cameras', 0}, 'cameras must be >= 1, got 0'}
};
for i = 1:numel(cases)
  args = cases{i}{1};
  expected = cases{i}{2};
  raised = false;
  try
    nrsfm_reconstruct(args{:});
  catch err
    raised = true;
    assert(strcmp(err.identifier, 'nrsfm:error'), ['identifier of ' expected]);
    assert(~isempty(strfind(err.message, expected)), ...
          sprintf('message "%s" lacks "%s"', err.message, expected));
  end
  assert(raised, ['no error for ' expected]);
end
fprintf('test_nrsfm_reconstruct: all checks passed\n');
