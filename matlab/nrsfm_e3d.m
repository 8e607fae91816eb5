function [e, Y] = nrsfm_e3d(S_true, S_est)
% NRSFM_E3D  e3D of Akhter et al. (their compareStructs), as nrsfm computes it.
%   e = nrsfm_e3d(S_true, S_est) compares two sequences of F shapes of P
%   points, each 3F x P with rows x_t, y_t, z_t (the layout of the Akhter
%   et al. files' S). Both are centred per frame; s is the mean over the 3F
%   rows of the truth's population standard deviation over the points; one
%   3 x 3 map Y for the whole sequence, the least-squares linear map from
%   estimate to truth followed by its nearest orthogonal matrix (reflection
%   allowed); e = mean_t mean_p ||X_tp - Y Xhat_tp|| / s (docs/metrics.md,
%   core/eval/metrics.h). Dimensionless.
%   [e, Y] = nrsfm_e3d(...) also returns the 3 x 3 alignment Y (an estimated
%   point X maps to Y * X; a covariance C to Y * C * Y').
if ~isequal(size(S_true), size(S_est)) || mod(size(S_true, 1), 3) ~= 0
  error('nrsfm:e3d', 'nrsfm_e3d: S_true and S_est must both be 3F x P');
end
F = size(S_true, 1) / 3;
X = S_true - repmat(mean(S_true, 2), 1, size(S_true, 2));
Xhat = S_est - repmat(mean(S_est, 2), 1, size(S_est, 2));
s = mean(std(X, 1, 2));
C = zeros(3);
M = zeros(3);
for t = 1:F
  rows = 3 * t - 2 : 3 * t;
  C = C + X(rows, :) * Xhat(rows, :)';
  M = M + Xhat(rows, :) * Xhat(rows, :)';
end
[U, ~, V] = svd(C * pinv(M));
Y = U * V';
total = 0;
for t = 1:F
  rows = 3 * t - 2 : 3 * t;
  D = X(rows, :) - Y * Xhat(rows, :);
  total = total + mean(sqrt(sum(D .^ 2, 1)));
end
e = total / F / s;
end
